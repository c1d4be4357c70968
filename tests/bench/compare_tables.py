"""Do the survey tables change?  This checkout against another (issue 27: the compiled kernel), side by side.

Usage (not a test; about 2 minutes with the compiled kernel, 10 with the numpy simulator of 6efc4a3)::

    git worktree add --detach /tmp/plbar-old 6efc4a3
    python tests/bench/compare_tables.py /tmp/plbar-old [--out DIR]

For three cases -- the default chain (161 forcing periods in [6, 14]), FE P1 N = 16 with end mass 0.5
(81 in [0.75, 2.25] T0_I) and the same with 1 % Rayleigh damping -- it runs the survey's chunks
(1,000 periods from rest, last 100 recorded) with each checkout in its own process, from rest and from a start
perturbed by 1e-13 (of the margin's size, on the first modal coordinate: the chaotic spread), and prints:

* kinds, stroboscopic periods and signatures of both;
* periodic motions: the largest relative difference of loss per period, xi_eq, xi_w, amplitude (the issue
  asks 1e-10);
* irregular motions, split by their sensitivity to the 1e-13 perturbation: the chaotic ones (it changes
  their loss by more than 1e-9) against the spread the perturbation makes; the insensitive ones (quasi-
  periodic) by the largest relative difference;
* the energy budget's largest residual (work - losses - change of energy, over the work).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

CODE = r'''
import json, sys, time
import numpy as np
import plbar
from plbar.motion import padded, Start, rest
from plbar.studies.survey.points import survey_chunk
name, perturb, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
chain = plbar.Case()
fe = plbar.Case(model="fe", n=16, end_mass=0.5)
T0 = fe.problem().system.T0[0]
cases = {"default": (chain, np.linspace(6, 14, 161)), "fe16": (fe, np.linspace(0.75 * T0, 2.25 * T0, 81)),
         "fe16d": (plbar.Case(model="fe", n=16, end_mass=0.5, rayleigh=plbar.rayleigh_from_ratio(0.01, 1.5, 4.5)),
                   np.linspace(0.75 * T0, 2.25 * T0, 81))}
case, T = cases[name]
pad = padded(case.problem())
rows, t0 = [], time.perf_counter()
for i in range(0, T.size, 41):
    s = rest(pad, T[i:i + 41].size)
    if perturb:
        eta = s.eta.copy()
        eta[:, 0] += perturb * pad.size[0]
        s = Start(s.state, eta, s.vel)
    rows += survey_chunk(case, T[i:i + 41], 1000, 100, start=s, pad=pad)[0]
json.dump({"rows": rows, "seconds": time.perf_counter() - t0, "plbar": plbar.__file__}, open(out, "w"))
'''

CASES = ("default", "fe16", "fe16d")


def generate(checkout: str, tag: str, out: Path) -> None:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(checkout))
    for name in CASES:
        for perturb, p in (("0", ""), ("1e-13", "p")):
            path = out / f"{tag}{p}_{name}.json"
            if not path.exists():
                subprocess.run([sys.executable, "-c", CODE, name, perturb, str(path)], env=env, check=True, cwd="/")


def _load(path: Path) -> dict:
    rows = json.load(open(path))["rows"]
    keys = set().union(*rows)
    return {k: np.array([r.get(k, np.nan) for r in rows]) for k in keys}


def _rel(a, b):
    return np.abs(a - b) / np.maximum(np.abs(b), 1e-300)


def compare(out: Path, name: str) -> dict:
    old, new, oldp, newp = (_load(out / f"{t}_{name}.json") for t in ("old", "new", "oldp", "newp"))
    ko, kn = old["kind"], new["kind"]
    rep = {"case": name, "T": int(ko.size), "same_kind": int(np.sum(ko == kn)),
           "kinds_old": {k: int(np.sum(ko == k)) for k in set(ko)},
           "kinds_new": {k: int(np.sum(kn == k)) for k in set(kn)}}
    per = (ko == "periodic") & (kn == "periodic")
    rep["periodic"] = int(per.sum())
    rep["same_m_and_signature"] = bool(np.array_equal(old["m"][per], new["m"][per]) and
                                       np.array_equal(old["signature"][per], new["signature"][per]))
    for col in ("loss_per_T", "xi_eq", "xi_w", "amp_c"):
        rep[f"periodic_{col}_max_rel"] = float(_rel(new[col], old[col])[per].max()) if per.any() else 0.0
    irr = (ko == "irregular") & (kn == "irregular")
    sens = np.maximum(_rel(oldp["loss_per_T"], old["loss_per_T"]), _rel(newp["loss_per_T"], new["loss_per_T"]))
    chaotic, quiet = irr & (sens > 1e-9), irr & ~(sens > 1e-9)
    rep["chaotic"], rep["insensitive"] = int(chaotic.sum()), int(quiet.sum())
    for col in ("loss_per_T", "xi_eq", "xi_w", "amp_c"):
        d = _rel(new[col], old[col])
        rep[f"chaotic_{col}_median_rel_new_vs_old"] = float(np.median(d[chaotic])) if chaotic.any() else 0.0
        rep[f"chaotic_{col}_median_rel_perturbed_vs_old"] = float(np.median(_rel(oldp[col], old[col])[chaotic])) \
            if chaotic.any() else 0.0
        rep[f"insensitive_{col}_max_rel"] = float(d[quiet].max()) if quiet.any() else 0.0
        if chaotic.sum() >= 5:         # new vs old drawn like a 1e-13 perturbation's spread? (two-sided U test)
            from scipy.stats import mannwhitneyu

            spread = np.concatenate([_rel(oldp[col], old[col])[chaotic], _rel(newp[col], new[col])[chaotic]])
            rep[f"chaotic_{col}_same_spread_p"] = float(mannwhitneyu(d[chaotic], spread).pvalue)
    rep["energy_residual_max_old"] = float(np.abs(old["energy_residual"]).max())
    rep["energy_residual_max_new"] = float(np.abs(new["energy_residual"]).max())
    return rep


def main(argv: list[str]) -> None:
    old = argv[0]
    out = Path(argv[argv.index("--out") + 1]) if "--out" in argv else Path(tempfile.mkdtemp(prefix="tables-"))
    out.mkdir(parents=True, exist_ok=True)
    here = str(Path(__file__).resolve().parents[2])
    generate(old, "old", out)
    generate(here, "new", out)
    reports = [compare(out, name) for name in CASES]
    for rep in reports:
        print(json.dumps(rep, indent=1))
    (Path(__file__).parent / "results_tables.json").write_text(json.dumps(reports, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
