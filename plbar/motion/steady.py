"""What a long simulation settled on: periodic (with its stroboscopic period) or not, and its energy accounts.

From the recorded periods of a :class:`plbar.motion.Run`:

* **kind**: ``periodic`` with stroboscopic period ``m`` when the states at the
  period boundaries repeat after ``m`` periods over the whole recorded window
  (relative distance below ``tol``), the smallest such ``m``, or when the caller
  has shown that the motion settles on a stable orbit of period ``m`` (``settled``,
  :mod:`plbar.studies.survey.settle`); otherwise ``irregular``; ``failed`` when the
  simulation stopped (a chattering contact).  A motion is never forced into a
  periodic label without that evidence.
* **impacts and loss per forcing period**: mean, min, max, standard deviation (of a periodic
  motion over whole orbits: the last ``m floor(R / m)`` recorded periods).
* **xi_eq of the motion** (FORMULATION §8): the mean impact loss per period over
  ``2 x`` the mean per period of ``sum_alpha sum_j w_j^alpha int etadot_j^2`` over the
  segments of each state; for the paper's class this is Eq. (22).  Its spread
  is that of the per-period ratios.
* **xi_w**: the same balance with one frequency for all modes, the forcing's:
  mean loss / (``2 W`` x mean ``int v^T M v``) (viscous damping ``c = 2 xi W M``).
* the contact amplitude (largest ``-x_c`` per period: mean and largest), the
  fraction of time stuck, and the energy budget of the whole run.
* **steadiness** (issue 29): the trend of the per-period loss and of ``int v^T M v`` (the energy in the bar's
  motion) over the recorded window, by batch means (:data:`BATCHES` windows, a straight line through their
  means): ``drift_*`` is the line's change across the window relative to the mean, and an irregular motion is
  ``steady`` unless one of them changes by more than :data:`DRIFT_TOL` with a slope significant at 1 %
  (``|t| > T_CRIT``, ``BATCHES - 2`` degrees of freedom); a periodic motion is steady (its states repeat), a
  failed one is not.  An undamped bar whose impacts keep feeding its
  high modes is not steady: its ``xi_eq`` and ``xi_w`` are then the window's values, not steady ones.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.batch import Batch
from ..util.reprs import build, rng
from .run import Run

__all__ = ["KINDS", "M_MAX", "PERIODIC_TOL", "Steady", "periodicity", "steady", "trend", "BATCHES", "DRIFT_TOL",
           "T_CRIT"]

KINDS = ("periodic", "irregular", "failed")
PERIODIC_TOL = 1e-6   #: relative distance of the boundary states below which a motion repeats
M_MAX = 12            #: longest stroboscopic period looked for
BATCHES = 10          #: windows of the steadiness test
DRIFT_TOL = 0.05      #: relative change across the recorded window above which a significant trend is a drift
T_CRIT = 3.355        #: Student's t at 1 % (two-sided), BATCHES - 2 = 8 degrees of freedom


@dataclass(frozen=True)
class Steady(Batch):
    """The steady motion of each trajectory of a run (arrays of shape (B,)).

    ``kind`` holds indices into :data:`KINDS`; ``m`` is 0 unless periodic; ``distance``
    is the relative repeat distance at ``m`` (at the best ``m`` when irregular).
    """

    T: np.ndarray
    kind: np.ndarray
    m: np.ndarray
    distance: np.ndarray
    impacts_per_T: np.ndarray
    loss_per_T: np.ndarray
    loss_min: np.ndarray
    loss_max: np.ndarray
    loss_std: np.ndarray
    xi_eq: np.ndarray
    xi_min: np.ndarray
    xi_max: np.ndarray
    xi_std: np.ndarray
    xi_w: np.ndarray
    amp_c: np.ndarray
    amp_c_max: np.ndarray
    stuck_fraction: np.ndarray
    work_per_T: np.ndarray
    energy_residual: np.ndarray
    viscous_per_T: np.ndarray = None
    drift_loss: np.ndarray = None
    drift_vMv: np.ndarray = None
    steady: np.ndarray = None

    def __len__(self) -> int:
        return self.T.size

    @property
    def kind_names(self) -> np.ndarray:
        return np.array(KINDS)[self.kind]

    def __repr__(self) -> str:
        counts = {k: int(np.sum(self.kind == i)) for i, k in enumerate(KINDS)}
        return build("Steady", {"B": len(self), "T": rng(self.T), "kinds": counts, "xi_eq": rng(self.xi_eq),
                                "loss_per_T": rng(self.loss_per_T)})


def periodicity(x, v, m_max: int = M_MAX, tol: float = PERIODIC_TOL):
    """Smallest repeat ``m`` of boundary states ``(B, R + 1, n)`` and its distance (``m = 0``: none up to ``m_max``).

    The distance at ``m`` is ``max_r |z_(r+m) - z_r| / max_r |z_r|`` over the
    window, ``z = (x, v)``; ``m`` is used only if the window holds at least
    two repeats (``R >= 2 m``).  A window too short for any such ``m`` (one
    recorded period) is never periodic; its distance is then the one repeat
    at ``m = 1`` it holds (finite, so that the table can hold it).
    """
    z = np.concatenate([x, v], axis=2)
    B, R1, _ = z.shape
    scale = np.maximum(np.linalg.norm(z, axis=2).max(axis=1), 1e-300)
    best_m = np.zeros(B, int)
    best_d = np.full(B, np.inf)
    for m in range(1, min(m_max, (R1 - 1) // 2) + 1):
        dist = np.linalg.norm(z[:, m:] - z[:, :-m], axis=2).max(axis=1) / scale
        new = (best_m == 0) & (dist <= tol)
        best_m[new] = m
        best_d = np.where(new | ((best_m == 0) & (dist < best_d)), dist, best_d)
    if R1 == 2:                                        # one recorded period: the one repeat it has, never periodic
        best_d = np.linalg.norm(z[:, 1] - z[:, 0], axis=1) / scale
    return best_m, best_d


def trend(a, batches: int = BATCHES) -> tuple[np.ndarray, np.ndarray]:
    """``(drift, t)`` of each row of ``a`` (B, R): the change across the window of the straight line through the
    means of ``batches`` consecutive windows, relative to the mean of the row, and the slope's Student ``t``
    (0 where the row is constant; ``inf`` where the batch means lie on the line exactly)."""
    a = np.asarray(a, float)
    B, R = a.shape
    nb = min(batches, R)
    if nb < 3:
        return np.zeros(B), np.zeros(B)
    edges = np.linspace(0, R, nb + 1).round().astype(int)
    means = np.stack([a[:, i:j].mean(axis=1) for i, j in zip(edges[:-1], edges[1:])], axis=1)    # (B, nb)
    x = 0.5 * (edges[:-1] + edges[1:]) - 0.5 * R
    sxx = float(x @ x)
    slope = (means - means.mean(axis=1, keepdims=True)) @ x / sxx
    resid = means - means.mean(axis=1, keepdims=True) - slope[:, None] * x[None, :]
    se = np.sqrt((resid ** 2).sum(axis=1) / (nb - 2) / sxx)
    mean = np.abs(a.mean(axis=1))
    with np.errstate(divide="ignore", invalid="ignore"):
        drift = np.where(mean > 0, slope * R / mean, 0.0)
        t = np.where(slope == 0, 0.0, np.where(se > 0, slope / se, np.inf))
    return drift, t


def _repeat(r: Run, b: int, m: int, default: float) -> float:
    """The relative repeat distance of trajectory ``b``'s window at ``m`` (:func:`periodicity`), ``default``
    where the window is not longer than ``m``."""
    z = np.concatenate([r.strobe_x[b], r.strobe_v[b]], axis=1)
    if z.shape[0] <= m:
        return float(default)
    scale = max(float(np.linalg.norm(z, axis=1).max()), 1e-300)
    return float(np.linalg.norm(z[m:] - z[:-m], axis=1).max() / scale)


def _spread(a, use):
    """Mean, min, max and standard deviation of each row over its ``use``d periods."""
    rows = [a[b][use[b]] for b in range(a.shape[0])]
    return tuple(np.array([f(x) for x in rows]) for f in (np.mean, np.min, np.max, np.std))


def steady(r: Run, m_max: int = M_MAX, tol: float = PERIODIC_TOL, settled=None) -> Steady:
    """Characterise the recorded window of ``r`` (needs ``r.record >= 1``).

    ``settled`` (int array (B,), optional): periods of the exact orbits that the caller has shown trajectories
    to be on, or to settle on though the window does not repeat to ``tol`` yet
    (:mod:`plbar.studies.survey.settle`); they are reported periodic with that period, averaged over whole
    orbits of it, their ``distance`` the repeat distance at it (0: no such evidence).  The orbit's period
    replaces the window's repeat: a motion settling on an orbit of period 1 may repeat to ``tol`` at ``m = 7``
    first (a slow approach that turns by about ``2 pi / 7`` a period), and its row must not name one period
    and average over another (issue 44).
    """
    if r.record < 1:
        raise ValueError("the run recorded no period; give record >= 1")
    m, dist = periodicity(r.strobe_x, r.strobe_v, m_max, tol)
    if settled is not None:
        settled = np.asarray(settled, int)
        for b in np.flatnonzero((settled > 0) & (settled != m) & (r.status == 0)):
            m[b], dist[b] = settled[b], _repeat(r, b, int(settled[b]), dist[b])
    kind = np.where(r.status != 0, 2, np.where(m > 0, 0, 1))
    m = np.where(kind == 0, m, 0)
    # a periodic motion is averaged over whole orbits: the last m floor(R / m) periods
    R = r.record
    use = np.ones(r.loss.shape, bool)
    for b in np.flatnonzero(m > 1):
        use[b, :R - m[b] * (R // m[b])] = False
    per_T = lambda a: np.array([a[b][use[b]].mean() for b in range(a.shape[0])])
    loss = per_T(r.loss)
    _, l_min, l_max, l_std = _spread(r.loss, use)
    with np.errstate(divide="ignore", invalid="ignore"):
        per = np.where(r.d_eq > 0, r.loss / (2 * r.d_eq), 0.0)
        den = per_T(r.d_eq)
        xi = np.where(den > 0, loss / (2 * den), 0.0)
        W = 2 * np.pi / r.T
        dw = per_T(r.d_w)
        xi_w = np.where(dw > 0, loss / (2 * W * dw), 0.0)
    _, x_min, x_max, x_std = _spread(per, use)
    stuck = np.array([r.stuck[b][use[b]].sum() / (use[b].sum() * r.T[b]) for b in range(r.T.size)])
    amp_max = np.array([r.amp[b][use[b]].max() for b in range(r.T.size)])
    d_loss, t_loss = trend(r.loss)
    d_vmv, t_vmv = trend(r.d_w)
    drifting = ((np.abs(d_loss) > DRIFT_TOL) & (np.abs(t_loss) > T_CRIT)) | \
        ((np.abs(d_vmv) > DRIFT_TOL) & (np.abs(t_vmv) > T_CRIT))
    return Steady(r.T, kind, m, dist, per_T(r.impacts.astype(float)), loss, l_min, l_max, l_std, xi, x_min, x_max,
                  x_std, xi_w, per_T(r.amp), amp_max, stuck, per_T(r.work_rec), r.energy_residual,
                  per_T(r.viscous_rec) if r.viscous_rec is not None else np.zeros(r.T.size), d_loss, d_vmv,
                  ((kind == 0) | (~drifting & (kind == 1))).astype(int))      # a periodic motion repeats: steady
