"""The survey of the continuum bar (``--model continuum``): :func:`plbar.continuum.simulate` at every forcing period,
its accounts as a :class:`plbar.motion.Run`, so that the survey characterises it as it does a mesh.

The continuum is the N = infinity row of ``plbar survey -N ...``.  Its motions are characterised exactly as the
FE bar's (:func:`plbar.motion.steady`: periodicity of the stroboscopic grid states, loss, ``xi_w``, contact
amplitude, time stuck, the drift test), with two differences that are results, not gaps:

* undamped, ``xi_eq`` (Eq. (22)) is not defined: its denominator ``sum_j omega_j Psi_j`` is
  ``int <v, (-c^2 d^2/dx^2)^(1/2) v>`` over the continuum's infinitely many modes, infinite as soon as the velocity
  has a jump (an impact's front is not in ``H^(1/2)``), so on a mesh ``xi_eq -> 0`` under refinement; the columns
  are blank (nan);
* no exact periodic orbit is polished: with an end mass every plastic impact emits a velocity jump that the undamped
  continuum carries forever (docs/continuum.md), so it has no periodic response with an impact loss.

With Rayleigh damping (a Kelvin-Voigt bar) the motions come from :func:`plbar.continuum.simulate_modal` (exact
modes of each contact state, ``case.modes`` of them, default :data:`MODAL_MODES`): the damping smooths the jumps,
so ``xi_eq`` is defined and filled; the Rayleigh dissipation (and the truncation's energy change at the switches,
1e-4 of the work) is the run's ``viscous`` term.
"""

from __future__ import annotations

import numpy as np

from ...app import Case
from ...errors import PlbarError
from ...motion import CHATTER, FREE, OK, STUCK, Run, Start
from ...util.progress import message
from ...util.record import events

__all__ = ["continuum_run", "continuum_runs", "as_run", "NO_XI_EQ", "MODAL_MODES", "blank_columns"]

#: the modes per contact state of the damped continuum when ``case.modes`` is not given (docs/continuum.md: the
#: 1,000-period loss agrees with 512 modes to 1e-9, the first 20 periods with 2,048 to 2e-4 in ``u(L)``)
MODAL_MODES = 1024

#: the survey's columns that the continuum leaves blank (``xi_eq`` is not defined: see the module's docstring)
NO_XI_EQ = ("xi_eq", "xi_min", "xi_max", "xi_std", "xi_total")


def blank_columns(case: Case) -> tuple:
    """The survey's columns the continuum of ``case`` leaves blank: ``xi_eq`` undamped (not defined), none damped."""
    return () if case.rayleigh is not None else NO_XI_EQ


def _simulate(case: Case, bar, T: float, periods: int, record: int):
    from ...continuum import simulate, simulate_modal

    if case.rayleigh is None:
        return simulate(bar, T, periods=periods, steps_per_L=case.n_eff, record=record)
    return simulate_modal(bar, T, periods, case.rayleigh, modes=case.modes or MODAL_MODES, keep=0, record=record,
                          grid=case.n_eff)


def continuum_runs(case: Case, T, periods: int, record: int, progress=None) -> list:
    """:func:`plbar.continuum.simulate` (damped: :func:`~plbar.continuum.simulate_modal`) from rest at every
    forcing period (None where the march stopped: chatter)."""
    bar = case.continuum()
    out = []
    for t in np.asarray(T, float):
        try:
            out.append(_simulate(case, bar, float(t), int(periods), int(record)))
        except (RuntimeError, PlbarError) as exc:          # the march stops where switches accumulate
            message(f"plbar: continuum at T = {t:g}: {exc}")
            out.append(None)
        if progress is not None:
            progress(int(periods))
    return out


def _stuck_time(cr, p: int) -> float:
    """Time stuck in period ``p`` of a continuum run: from its state at the period's start and its switches."""
    T = cr.T
    t, stuck, total = p * T, bool(cr.end[p, 2]), 0.0
    ev = cr.events
    sel = (ev["time"] >= p * T) & (ev["time"] < (p + 1) * T)
    for te, k in zip(ev["time"][sel], ev["kind"][sel]):
        if stuck:
            total += te - t
        t, stuck = te, k == 2                        # 2 an impact (plastic: stuck), 1 an opening
    return total + ((p + 1) * T - t if stuck else 0.0)


def as_run(runs, T, periods: int, record: int, n: int) -> Run:
    """The continuum runs as one :class:`plbar.motion.Run` of ``B = len(T)`` trajectories (stroboscopic states on
    the ``n`` free grid points; a stopped march has status ``CHATTER`` and nan accounts)."""
    T = np.asarray(T, float)
    B, R = T.size, int(record)
    nan = lambda *shape: np.full(shape, np.nan)  # noqa: E731
    f = {k: nan(B, R) for k in ("loss", "d_eq", "d_w", "work_rec", "stuck", "amp")}
    imp, opn = np.zeros((B, R), int), np.zeros((B, R), int)
    sx, sv, ss = nan(B, R + 1, n), nan(B, R + 1, n), np.full((B, R + 1), STUCK)
    status = np.full(B, OK)
    work, losses, e0, e1, visc = (np.zeros(B) for _ in range(5))
    visc_rec = np.zeros((B, R))
    ev = []
    for b, cr in enumerate(runs):
        if cr is None:
            status[b] = CHATTER
            continue
        f["loss"][b], f["work_rec"][b], f["amp"][b] = cr.loss[-R:], cr.work[-R:], cr.amp[-R:]
        f["d_w"][b] = cr.v2[-R:]
        if hasattr(cr, "psi"):                              # damped (modal): xi_eq defined, viscous losses
            f["d_eq"][b] = cr.psi[-R:]
            vp = cr.dissipation + cr.transfer
            visc[b], visc_rec[b] = vp.sum(), vp[-R:]
        f["stuck"][b] = [_stuck_time(cr, p) for p in range(periods - R, periods)]
        imp[b], opn[b] = cr.impacts[-R:], cr.openings[-R:]
        sx[b], sv[b] = cr.strobe_u[:, 1:], cr.strobe_v[:, 1:]
        ss[b] = np.where(cr.end[-(R + 1):, 2] > 0, STUCK, FREE)
        work[b], losses[b], e0[b], e1[b] = cr.work.sum(), cr.loss.sum(), cr.energy[0], cr.energy[-1]
        keep = cr.events[cr.events["time"] >= (periods - R) * cr.T].copy()
        keep["traj"] = b
        ev.append(keep)
    return Run(T=T, phi=np.zeros(B), status=status, events=np.concatenate(ev) if ev else events([], [], []),
               periods=int(periods), record=R, impacts=imp, openings=opn, loss=f["loss"], d_eq=f["d_eq"],
               d_w=f["d_w"], work_rec=f["work_rec"], stuck=f["stuck"], amp=f["amp"], strobe_x=sx, strobe_v=sv,
               strobe_state=ss, work=work, losses=losses, energy0=e0, energy_end=e1,
               final=Start(ss[:, -1], np.zeros((B, 0)), np.zeros((B, 0))), rounds=0, viscous=visc,
               viscous_rec=visc_rec)


def continuum_run(case: Case, T, periods: int, record: int, progress=None) -> Run:
    """The continuum of ``case`` simulated from rest at forcing periods ``T``, as one :class:`Run`."""
    return as_run(continuum_runs(case, T, periods, record, progress), T, periods, record, case.n_eff)
