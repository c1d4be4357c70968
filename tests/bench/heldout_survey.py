"""Held-out check of the survey's labels against an independent simulator (issue 28).

81 forcing periods of the default case (T = 6, 6.1, ..., 14), 600 forcing periods from rest.  The
independent label comes from :func:`plbar.check.simulate` alone (sampled events refined by brentq, its own
flows and switches; nothing of :mod:`plbar.motion` or :mod:`plbar.periodic`):

* the simulation runs 600 periods from rest; where the repeat distance of its last stroboscopic states is
  below ``3e-2`` (a candidate), it is carried on, up to ``EXTRA`` more periods, until the states repeat;
* **periodic with period m** when, at some point, the last ``2 m + 1`` stroboscopic states repeat after
  ``m`` periods to ``1e-8`` of their size: the motion truly settled; ``m`` is the smallest such period
  after ``2 CHUNK`` more periods, or its smallest divisor whose last states repeat to ``1e-5`` (a slow
  approach through complex multipliers can make a multiple of the period repeat first);
* **irregular** otherwise.

The survey (``plbar.survey``, 600 periods from rest, its default record) is then compared: a periodic
motion must be reported ``periodic`` with the same ``m``, and its exact loss per period (the polished
orbit) must equal the independent simulator's last period's loss to ``1e-6``; an irregular motion must be
reported ``irregular``.

Usage (not a test; about 15 minutes on 2 cores: a slow approach is followed up to 20,600 periods)::

    python tests/bench/heldout_survey.py [--save tests/bench/results_heldout.json]
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

PERIODS = 600
EXTRA = 20000         #: periods a candidate may be carried on
CHUNK = 200           #: periods per continuation step
REPEAT = 1e-8
CANDIDATE = 3e-2
M_MAX = 12


def _repeat(z, m_max=M_MAX):
    """Smallest m whose last 2m+1 states repeat to REPEAT (0 if none), and the best end distance."""
    scale = max(np.linalg.norm(z, axis=1).max(), 1e-300)
    best = np.inf
    for m in range(1, m_max + 1):
        if z.shape[0] < 2 * m + 1:
            break
        tail = z[-(2 * m + 1):]
        d = np.linalg.norm(tail[m:] - tail[:-m], axis=1).max() / scale
        best = min(best, d)
        if d <= REPEAT:
            return m, d
    return 0, best


def independent(T: float) -> dict:
    from plbar import Case
    from plbar.check import simulate

    prob = Case().problem()
    n = prob.system.M.shape[0]
    s = simulate(prob, T, 0.0, np.zeros(n), np.zeros(n), 1, PERIODS)
    zs = [np.concatenate([s.strobe_x, s.strobe_v], axis=1)]
    done = PERIODS
    m, d = _repeat(zs[0][-40:])
    d_600 = d
    last = s
    while m == 0 and d <= CANDIDATE and done < PERIODS + EXTRA:
        last = simulate(prob, T, 0.0, last.x, last.v, last.state, CHUNK, t0=done * T)
        zs.append(np.concatenate([last.strobe_x, last.strobe_v], axis=1))
        done += CHUNK
        m, d = _repeat(np.concatenate(zs)[-40:])
    if m and done > PERIODS:
        for _ in range(2):
            last = simulate(prob, T, 0.0, last.x, last.v, last.state, CHUNK, t0=done * T)
            zs.append(np.concatenate([last.strobe_x, last.strobe_v], axis=1))
            done += CHUNK
        m, d = _repeat(np.concatenate(zs)[-40:])
        z = np.concatenate(zs)[-40:]
        scale = np.linalg.norm(z, axis=1).max()
        tail = z[-(2 * m + 1):]
        for p in range(1, m):            # a divisor of m that repeats too: the orbit's own period
            if m % p == 0 and np.linalg.norm(tail[p:] - tail[:-p], axis=1).max() <= 1e-5 * scale:
                m = p
                break
    out = {"T": T, "m": int(m), "distance_600": float(d_600), "distance": float(d), "periods": done}
    if m:
        t_end = last.t_end
        imp = last.impact_times >= t_end - m * T * (1 - 1e-9)
        out["loss_per_T"] = float(last.impact_losses[imp].sum() / m)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--save", default=None)
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args(argv)
    import plbar
    from plbar.studies.survey import survey

    T = np.round(np.linspace(6.0, 14.0, 81), 10)
    t0 = time.perf_counter()
    sv = survey(plbar.Case(), T, periods=PERIODS)
    t_survey = time.perf_counter() - t0
    with ProcessPoolExecutor(a.workers) as ex:
        ind = list(ex.map(independent, T.tolist()))
    t_ind = time.perf_counter() - t0 - t_survey
    tab = sv.rows("rest")
    rows, per_ok, per_n, irr_ok, irr_n = [], 0, 0, 0, 0
    for i, t in enumerate(T):
        r = ind[i]
        kind, m = str(tab["kind"][i]), int(tab["m"][i])
        ex_loss = float(tab["exact_loss"][i])
        if r["m"]:
            per_n += 1
            good = kind == "periodic" and m == r["m"] and abs(ex_loss - r["loss_per_T"]) <= 1e-6 * r["loss_per_T"]
            per_ok += good
        else:
            irr_n += 1
            good = kind == "irregular"
            irr_ok += good
        rows.append({**r, "survey_kind": kind, "survey_m": m, "survey_exact_loss": ex_loss,
                     "survey_signature": str(tab["signature"][i]), "agree": bool(good)})
        if not good or (r["m"] and r["distance_600"] > 1e-6):
            print(f"T = {t:5.2f}  independent m = {r['m']} (repeat {r['distance_600']:.1e} at 600, "
                  f"{r['distance']:.1e} at {r['periods']})  survey: {kind} m = {m} {tab['signature'][i]}"
                  f"  {'ok' if good else 'DISAGREE'}")
    print(f"periodic {per_ok}/{per_n}, irregular {irr_ok}/{irr_n}  "
          f"(survey {t_survey:.1f} s, independent {t_ind:.0f} s)")
    if a.save:
        with open(a.save, "w") as f:
            json.dump({"periodic": [per_ok, per_n], "irregular": [irr_ok, irr_n], "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
