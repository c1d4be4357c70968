"""The periodic responses of every signature in a run: the search window, the extra seeds, the table rows, the summary.

:class:`Search` is what :func:`plbar.solve` begins beside the paper's class
(:func:`plbar.find_paths`), for ``Case.signatures`` ``"default"`` or ``"all"``
(:func:`plbar.periodic.find_hybrid`): besides the seeds of the structure (the zero-dwell
class, period doublings, admissibility ends), the periodic motions of a simulation from
rest across the window (``"default"``: 81 forcing periods, 600 periods each, the last 60
recorded; ``"all"``: 161, 1,000 and 100, as ``plbar survey``, and orbits up to ``m = 8``)
are polished (:func:`plbar.periodic.from_motion`) and followed.  Their rows
join the paper's in ``paths.csv`` with the columns ``m, k, signature,
loss_per_T, durations``; ``T1`` and ``T2`` are then the total stuck and free
time over the orbit (``m`` periods) and ``dPL`` the loss over the orbit.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor, wait

import numpy as np

from ..periodic import NotConverged, canonical, find_hybrid, from_motion, prepare
from ..periodic import compiled as chain_compiled
from ..motion import COMPILE_NOTE, compile_elsewhere, compiled, halt_flag, padded, run, steady
from ..model import Problem
from ..paths import Domain, Paths
from ..util.progress import message, progress_bar
from ..util.threads import signals_to_main

__all__ = ["Search", "hybrid_window", "hybrid_rows", "hybrid_summary", "SEED_PERIODS"]

#: forcing periods, periods simulated, periods recorded of the seeding simulation, per kind
SEED_PERIODS = {"default": (81, 600, 60), "all": (161, 1000, 100)}


def hybrid_window(prob: Problem, domain: Domain) -> tuple[float, float]:
    """Forcing periods searched: from ``T0^I / 2`` to the top of the paper's search domain ``max T1 + max T2``."""
    T0I, _ = prob.system.T0
    return 0.5 * T0I, float(domain.T1[1] + domain.T2[1])


def _seeding(prob: Problem, window, kinds: str, progress=None, pad=None, halt=None):
    """The seeding simulation: ``SEED_PERIODS[kinds]`` forcing periods across ``window`` from rest, the switches
    only (``progress(n)`` after each block of periods; ``halt``: its kernel's halt flag, :func:`plbar.motion.run`)."""
    num, periods, record = SEED_PERIODS[kinds]
    T = np.linspace(window[0], window[1], num)
    return run(padded(prob) if pad is None else pad, T, 0.0, periods, record, progress=progress, accounts=False,
               halt=halt)


def _seeds(prob: Problem, r, kinds: str, progress: bool = False) -> list:
    """Orbits polished (:func:`plbar.periodic.from_motion`) from the periodic motions of the seeding simulation
    ``r``."""
    _, periods, record = SEED_PERIODS[kinds]
    s = steady(r, tol=1e-4)
    periodic = np.flatnonzero(s.kind == 0)
    out = []
    with progress_bar(periodic.size, progress, "signatures: polishing the periodic motions", "motion") as bar:
        for b in periodic:
            out += _seed(prob, r, int(b), int(s.m[b]), periods - record)
            bar.update(1)
    return out


def _seed(prob: Problem, r, b: int, m: int, first: int) -> list:
    """The orbit of ``m`` periods polished from motion ``b`` of ``r``, its periods from ``first`` on (none where
    Newton fails)."""
    T = float(r.T[b])
    sel = r.events["traj"] == b
    te, ke = r.events["time"][sel], r.events["kind"][sel]
    after = te >= first * T
    try:
        return [from_motion(prob, T, m, first * T, r.strobe_x[b, 0], r.strobe_v[b, 0], int(r.strobe_state[b, 0]),
                            te[after], ke[after])]
    except (NotConverged, ValueError, np.linalg.LinAlgError):
        return []



class Search:
    """The other signatures of a run, begun before the paper's class is solved (:func:`plbar.solve`).

    What needs the case only starts at once, beside the paper's solve: after an install the compile of the
    simulator in another process (:func:`plbar.motion.compile_elsewhere`), else the seeding simulation in a
    thread (the compiled kernel releases the GIL).  :meth:`finish` does the rest once the paper's branches are
    known: the chain compiled or loaded (:func:`plbar.periodic.prepare`), the seeds polished, the curves followed.
    :meth:`cancel` (or leaving the ``with`` block, a Ctrl-C) stops what still runs: the simulation's kernel at its
    next round (its halt flag, :func:`plbar.motion.halt_flag`), the compile elsewhere at once.
    """

    def __init__(self, prob: Problem, domain: Domain, kinds: str, progress: bool = False):
        self.prob, self.kinds, self.progress = prob, kinds, progress
        self.window = hybrid_window(prob, domain)
        self.pad = padded(prob)
        self.done, self._halt = 0, halt_flag()
        self._other = self._pool = self._future = None
        if compiled(self.pad, accounts=False):
            self._pool = ThreadPoolExecutor(1, thread_name_prefix="plbar-seeding", initializer=signals_to_main)
            self._future = self._pool.submit(_seeding, prob, self.window, kinds, self._count, self.pad, self._halt)
        else:
            self._other = compile_elsewhere(self.pad, accounts=False)
        if progress and not (self._other is None and chain_compiled(prob)):
            message(f"plbar: {COMPILE_NOTE}")

    def _count(self, n: int) -> None:
        self.done += n

    def _simulation(self):
        num, periods, _ = SEED_PERIODS[self.kinds]
        desc = f"signatures: simulating {num} forcing periods from rest"
        if self._future is None:                       # compiled elsewhere meanwhile: simulate here
            self._other.wait()
            with progress_bar(periods, self.progress, desc, "period") as bar:
                return _seeding(self.prob, self.window, self.kinds, bar.update, self.pad, self._halt)
        with progress_bar(periods, self.progress, desc, "period", initial=self.done) as bar:
            shown = self.done
            while not self._future.done():
                wait([self._future], timeout=0.2)
                bar.update(self.done - shown)
                shown = self.done
            return self._future.result()

    def finish(self, paths: Paths) -> list:
        """The branches of every signature but the paper's class (:func:`plbar.periodic.find_hybrid`), seeded by the
        paper's branches ``paths`` and the simulation."""
        try:
            with progress_bar(1, self.progress, "signatures: loading the chain's kernel", "step"):
                prepare(self.prob, paths.branches)
            seeds = _seeds(self.prob, self._simulation(), self.kinds, self.progress)
            # the seeds of the structure come first (zero-dwell grid, doublings, branch ends), then each curve
            with progress_bar(None, self.progress, "signatures: seeding the curves", "curve") as bar:
                def curve():
                    bar.set_description("signatures: following curves")
                    bar.update(1)

                return find_hybrid(self.prob, self.window, paths.branches, seeds, kinds=self.kinds,
                                   m_max=4 if self.kinds == "default" else 8, progress=curve)
        finally:
            self.cancel()

    def cancel(self) -> None:
        """Stop the simulation (its kernel at its next round) or the compile elsewhere; wait for them."""
        self._halt[0] = 1
        if self._other is not None:
            self._other.cancel()
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.cancel()
        return False


def hybrid_rows(branches, first_id: int) -> dict:
    """The ``paths.csv`` columns of the hybrid branches (ids from ``first_id``)."""
    cols: dict = {}
    for j, b in enumerate(branches):
        for o in b.orbits:
            _, d, phi = canonical(o)                 # the durations and phase of the canonical rotation
            row = {"branch": first_id + j, "T1": float(d[0::2].sum()), "T2": float(d[1::2].sum()),
                   "phi": phi, "T": o.T, "dPL": o.dPL, "xi": o.xi, "grazing": 0, "omega": 2 * np.pi / o.T,
                   "xi_w": o.xi_w, "viscous_loss": o.viscous, "zeta_rayleigh": o.xi_total - o.xi,
                   "xi_total": o.xi_total, "m": o.sig.m, "k": o.sig.k, "signature": b.label, "loss_per_T": o.loss_per_T,
                   "durations": ";".join(f"{x:.17g}" for x in d), "max_abs_xc": o.amplitude}
            for k, v in row.items():
                cols.setdefault(k, []).append(v)
        for k, v in (("stable", b.stable.astype(int)), ("max_abs_multiplier", b.max_abs_multiplier)):
            cols.setdefault(k, []).extend(v.tolist())
    return cols


def hybrid_summary(branches, first_id: int) -> list[dict]:
    """One entry per hybrid branch for ``summary.json``."""
    out = []
    for j, b in enumerate(branches):
        out.append({"branch": first_id + j, "signature": b.label, "family": b.sig.family, "m": b.sig.m, "k": b.sig.k,
                    "points": len(b),
                    "T_range": [float(b.T.min()), float(b.T.max())],
                    "xi_range": [float(b.xi.min()), float(b.xi.max())],
                    "loss_per_T_range": [float(b.loss_per_T.min()), float(b.loss_per_T.max())],
                    "stable_points": int(b.stable.sum()),
                    "events": [{"kind": e["kind"], "index": int(e["index"]), "T": float(e["T"])} for e in b.events]})
    return out
