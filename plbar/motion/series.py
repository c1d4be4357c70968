"""A motion of the two-state system as a time series (:class:`Series`): a simulated window or a periodic orbit.

A motion between events is exact: each piece is the closed-form modal flow of one contact state
(:func:`plbar.response.segment`) from its start.  :class:`Series` holds the pieces (start time, state, modal
state) and evaluates any number of times at once, vectorised over the samples (the pieces are found with
``searchsorted``, each state's samples flowed in one call); it answers what :func:`plbar.io.motion_data` and
:func:`plbar.io.response_data` ask (the physical states, the contact reaction, the energies).  Two builders make the
pieces: :func:`motion_series` from a simulated :class:`Run` (here) and :func:`plbar.periodic.orbit_series` from a
periodic orbit of any signature.

The pieces come in *blocks*: a sample at ``t`` uses the pieces of block ``floor((t - t0) / block)`` only.  A
simulated window restarts each forcing period from the kernel's own boundary state (the block is ``T``), so the
series is exact at the boundaries and an irregular motion's sensitivity cannot carry round-off from one period to
the next; :func:`boundary_mismatch` measures how well the flows carry each boundary state to the next (round-off).
An orbit is one block.

A simulated window's pieces start from the boundary of each period and switch at each of its events (opening:
the state I modes seen by state II, ``P12``; impact: ``P21`` for positions, ``Q21`` for velocities, the contact DOF
stopped, Eq. (10); a rebound with a coefficient of restitution: Newton's law along the contact DOF, the gap still
open).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..model import Problem
from ..response import segment
from .model import STUCK
from .run import Run

__all__ = ["Series", "motion_series", "boundary_mismatch", "SNAP"]

SNAP = 1e-9   #: an event within ``SNAP * T`` after a boundary belongs to the period before it (the boundary state)


@dataclass(frozen=True)
class Series:
    """A motion sampled at any times of its window ``[t0, t0 + span]`` (see the module docstring).

    Attributes
    ----------
    prob : Problem
        The problem (its system and load).
    T, phi : float
        Forcing period and phase (load ``q cos(2 pi t / T - phi)``).
    t0, span : float
        Absolute start time of the window and its length (``periods T``).
    periods : int
        Forcing periods in the window.
    events : ndarray of dtype EVENT, shape (E,)
        The window's events (:data:`plbar.util.record.EVENT`).
    stuck_time, free_time : float
        Time in contact (state I) and with the gap open (state II) over the window.
    block : float
        Length of a block of pieces (``T`` for a simulated window, ``span`` for an orbit).
    starts : ndarray, shape (S,)
        Absolute start time of each piece, increasing within each block.
    blocks : ndarray of int, shape (S,)
        The block of each piece (non-decreasing).
    state : ndarray of int, shape (S,)
        1 in contact, 2 gap open.
    eta, vel : ndarray, shape (S, m)
        The modal state at each piece's start (its state's modes first, the rest 0; ``m`` the larger count).
    """

    prob: Problem = field(repr=False)
    T: float
    phi: float
    t0: float
    span: float
    periods: int
    events: np.ndarray = field(repr=False)
    stuck_time: float
    free_time: float
    block: float
    starts: np.ndarray = field(repr=False)
    blocks: np.ndarray = field(repr=False)
    state: np.ndarray = field(repr=False)
    eta: np.ndarray = field(repr=False)
    vel: np.ndarray = field(repr=False)

    # -- the pieces --------------------------------------------------------------------------------------------
    def _block_of(self, t: np.ndarray) -> np.ndarray:
        n = int(self.blocks[-1]) + 1
        k = np.floor((t - self.t0) / self.block + 1e-12).astype(int)
        return np.where(t < self.t0 + self.span, np.clip(k, 0, n - 1), n - 1)

    def _piece(self, t: np.ndarray, block: np.ndarray) -> np.ndarray:
        """The piece of each time: the last of its block that starts at or before it (one search per block)."""
        j = np.zeros(t.size, int)
        edges = np.searchsorted(self.blocks, np.arange(int(self.blocks[-1]) + 2))
        for k in np.unique(block):
            sel = block == k
            lo, hi = edges[k], edges[k + 1]
            j[sel] = lo + np.clip(np.searchsorted(self.starts[lo:hi], t[sel], side="right") - 1, 0, hi - lo - 1)
        return j

    def _modes(self, s: int):
        """``(w, f, zeta)`` of state ``s`` (``zeta`` None undamped)."""
        sy, prob = self.prob.system, self.prob
        damped = bool(getattr(sy, "damped", False))
        if s == 1:
            return sy.w1, np.asarray(prob.f1, float), sy.zeta1 if damped else None
        return sy.w2, np.asarray(prob.f2, float), sy.zeta2 if damped else None

    def modal(self, times, block=None):
        """The state ``(K,)`` (1 or 2) and the modal ``eta, etadot`` ``(K, m)`` (the state's modes first, the rest
        0) at absolute ``times`` (K,); ``block`` (K,) the block of pieces to flow from (default: the times')."""
        t = np.asarray(times, float).ravel()
        lo, hi = self.t0 - 1e-12 * self.span, self.t0 + self.span * (1 + 1e-12)
        if t.size and not (t.min() >= lo and t.max() <= hi):
            bad = t[(t < lo) | (t > hi)][0]
            raise InputError(f"t = {bad:.12g} is outside the window [{self.t0:.12g}, {self.t0 + self.span:.12g}]")
        j = self._piece(t, self._block_of(t) if block is None else np.asarray(block, int).ravel())
        st = self.state[j]
        eta, vel = np.zeros((t.size, self.eta.shape[1])), np.zeros((t.size, self.eta.shape[1]))
        W = 2 * np.pi / self.T
        for s in (1, 2):
            sel = st == s
            if not sel.any():
                continue
            w, f, zeta = self._modes(s)
            m, js = w.size, j[sel]
            ts = self.starts[js][:, None]
            eta[sel, :m], vel[sel, :m] = segment(w, f, W, ts, t[sel, None] - ts, self.eta[js, :m], self.vel[js, :m],
                                                 np.cos(self.phi), np.sin(self.phi), zeta=zeta,
                                                 accel=self.prob.statics.accel if s == 2 else None)
        return st, eta, vel

    # -- what the export asks ---------------------------------------------------------------------------------
    def response(self, times):
        """Physical ``x, v`` (K, n) and state (K,) (1 in contact, 2 gap open) at absolute ``times``."""
        st, eta, vel = self.modal(times)
        return (*_physical(self.prob, st, eta, vel), st)

    def reaction(self, times):
        """``-R`` (K,) in state I at ``times`` (0 in state II): the compression the wall holds."""
        sy, prob = self.prob.system, self.prob
        t = np.asarray(times, float).ravel()
        st, eta, vel = self.modal(t)
        one, m1 = st == 1, sy.w1.size
        rv = np.asarray(sy.r_v, float) if getattr(sy, "damped", False) else np.zeros(m1)
        out = np.zeros(t.size)
        W = 2 * np.pi / self.T
        out[one] = -(_dots(eta[one, :m1], sy.r_eta) + _dots(vel[one, :m1], rv)
                     + prob.r_q * np.cos(W * t[one] - self.phi) + prob.statics.reaction)
        return out

    def energies(self, times):
        """Kinetic and potential energy (Eqs. (12)-(13)) at ``times``; each (K,).  The potential energy is the
        structure's, ``x^T K x / 2``: the modal one plus the state's static energy (a gap's,
        :class:`plbar.model.Statics`)."""
        sy, es, g = self.prob.system, self.prob.statics.energy, self.prob.statics.accel
        st, eta, vel = self.modal(times)
        ek, ep = np.zeros(st.size), np.zeros(st.size)
        for s, w in ((1, sy.w1), (2, sy.w2)):
            sel, m = st == s, w.size
            ek[sel] = 0.5 * _dots(vel[sel, :m], vel[sel, :m])
            ep[sel] = 0.5 * np.sum((w * eta[sel, :m]) ** 2, axis=1) + es[s - 1]
            if s == 2 and g is not None:        # a constant load's potential on the rigid-body modes
                ep[sel] -= _dots(eta[sel, :m], g)
        return ek, ep


# -- a simulated window ------------------------------------------------------------------------------------------
def motion_series(prob: Problem, r: Run, b: int, periods: int | None = None) -> Series:
    """Trajectory ``b`` of a :class:`Run` over the last ``periods`` periods of its recorded window.

    Parameters
    ----------
    prob : Problem
        The problem the run simulated (its system and load).
    r : Run
        A run that recorded at least ``periods`` periods (``run(..., record=...)``).
    b : int
        The trajectory.
    periods : int, optional
        The last ``periods`` recorded periods (default: all of them).

    Returns
    -------
    Series
        Its events: ``kind`` 1 opening, 2 impact, 3 rebound, 4 the impact that ends a chattering sequence
        (recorded at its accumulation point).
    """
    R = int(r.record)
    P = R if periods is None else periods
    if isinstance(P, bool) or int(P) != P or not 1 <= P <= R:
        raise InputError(f"periods = {periods!r} must be an integer in [1, {R}] (the run recorded {R} periods)")
    P, b = int(P), int(b)
    T, phi = float(r.T[b]), float(r.phi[b])
    k0 = R - P
    t0 = (r.periods - R + k0) * T
    after = r.events["time"] > t0 + SNAP * T if t0 > 0 else r.events["time"] >= 0.0
    ev = r.events[(r.events["traj"] == b) & after]     # the run's start is before its events at t = 0 (see _pieces)
    state = np.asarray(r.strobe_state[b, k0:], int)
    pieces = _pieces(prob, T, phi, t0, ev, np.asarray(r.strobe_x[b, k0:], float),
                     np.asarray(r.strobe_v[b, k0:], float), state)
    stuck = _stuck_time(ev, t0, P * T, state[0] == STUCK)
    return Series(prob=prob, T=T, phi=phi, t0=t0, span=P * T, periods=P, events=ev, stuck_time=stuck,
                  free_time=P * T - stuck, block=T, **pieces)


def _pieces(prob, T, phi, t0, ev, x, v, state) -> dict:
    """The pieces of each period ``k``: from its boundary state, switched at each event in
    ``(t_k + SNAP T, t_{k+1} + SNAP T]`` (the last period: every event after its start)."""
    flow = _Flow(prob, T, phi)
    P = state.size - 1
    cols = max(prob.system.w1.size, prob.system.w2.size)
    out = {k: [] for k in ("starts", "blocks", "state", "eta", "vel")}
    for k in range(P):
        t = t0 + k * T
        s, e, u = flow.boundary(x[k], v[k], state[k])
        # a boundary state is recorded after the events at it, but the run's start is its initial state: an event
        # at t = 0 (a contact that opens at once: P2's wall reaction is round-off there) is still to come
        lo = np.searchsorted(ev["time"], t + SNAP * T, side="right") if t > 0 else 0
        hi = ev.size if k == P - 1 else np.searchsorted(ev["time"], t + (1 + SNAP) * T, side="right")
        for i in range(lo, hi + 1):
            for key, val in zip(out, (t, k, s, np.pad(e, (0, cols - e.size)), np.pad(u, (0, cols - u.size)))):
                out[key].append(val)
            if i == hi:
                break
            te, kind = float(ev["time"][i]), int(ev["kind"][i])
            if kind == 4:                  # the end of a chattering sequence: switched before it was recorded
                te = flow.stick_time(t, te, e, u)
            e, u = flow(s, t, te - t, e, u)
            s, e, u = flow.switch(s, kind, e, u)
            t = te
    return {k: np.array(val) for k, val in out.items()}


def _stuck_time(ev, t0: float, span: float, stuck: bool) -> float:
    """Time in contact over the window ``[t0, t0 + span]`` from its first state and its events."""
    total, t, s = 0.0, t0, 1 if stuck else 2
    for te, ke in zip(ev["time"], ev["kind"]):
        if te > t0 + span:
            break
        if s == 1:
            total += te - t
        s, t = (2 if ke == 1 else 1), te
    if s == 1:
        total += t0 + span - t
    return total


class _Flow:
    """The closed-form flows and switches of a problem at one forcing (what :func:`_pieces` carries with)."""

    def __init__(self, prob: Problem, T: float, phi: float):
        self.prob, self.T, self.phi = prob, T, phi

    def boundary(self, x, v, state):
        """A boundary state in the modal coordinates of its state: ``(state 1|2, eta, etadot)``."""
        sy = self.prob.system
        M = np.asarray(sy.M, float)
        if state == STUCK:
            Mr = M[:-1, :-1]
            return 1, sy.V1.T @ (Mr @ x[:-1]), sy.V1.T @ (Mr @ v[:-1])
        return 2, sy.V2.T @ (M @ x), sy.V2.T @ (M @ v)

    def __call__(self, s: int, ts: float, tau: float, e, v):
        sy, prob = self.prob.system, self.prob
        damped = bool(getattr(sy, "damped", False))
        w, f, zeta = (sy.w1, prob.f1, sy.zeta1 if damped else None) if s == 1 else \
            (sy.w2, prob.f2, sy.zeta2 if damped else None)
        return segment(w, np.asarray(f, float), 2 * np.pi / self.T, ts, tau, e, v, np.cos(self.phi),
                       np.sin(self.phi), zeta=zeta, accel=prob.statics.accel if s == 2 else None)

    def switch(self, s: int, kind: int, e, v):
        sy, st = self.prob.system, self.prob.statics
        if kind == 1:
            if s != 1:
                raise InputError("an opening of the gap recorded while it is open: not this run's events")
            return 2, sy.P12 @ e + st.open_offset, sy.P12 @ v
        if s != 2:
            raise InputError("an impact recorded in contact: not this run's events")
        if kind == 3:                      # a rebound: Newton's law along the contact DOF, the gap stays open
            g = np.asarray(sy.gap_row, float)
            return 2, e, v - (1.0 + float(self.prob.restitution)) * (g @ v) / (g @ g) * g
        return 1, sy.P21 @ e + st.impact_offset, sy.Q21 @ v

    def stick_time(self, t: float, te: float, e, v) -> float:
        """The time of the impact that ends a chattering sequence, recorded at ``te``: the simulator records it at
        the accumulation point of the rebounds it stands for, ``2 e v_c / (a (1 - e))`` after the impact, where
        it switched (:func:`plbar.motion.kernel.loop.rebound`).  The last return of the gap to zero in the free
        flight ``[t, te]`` (from the state ``e, v`` at ``t``)."""
        g, d = np.asarray(self.prob.system.gap_row, float), self.prob.statics.margin[1]
        xc = lambda u: float(g @ self(2, t, u - t, e, v)[0]) - d   # noqa: E731  (the stop at x_c = d)
        grid = np.linspace(t, te, 65)[1:]
        vals = np.array([xc(u) for u in grid])
        if not vals[-1] > 0:
            return te
        neg = np.flatnonzero(vals <= 0)
        if not neg.size:
            return te
        from scipy.optimize import brentq

        return float(brentq(xc, grid[neg[-1]], grid[neg[-1] + 1], xtol=1e-15 * max(abs(te), 1.0), rtol=1e-15))


def boundary_mismatch(series: Series, r: Run, b: int) -> float:
    """Largest distance between a boundary state carried over its period by the flows and the kernel's next
    boundary state, relative to the largest state of the window (round-off: the two integrations agree)."""
    P = series.periods
    k0 = int(r.record) - P
    xs, vs = np.asarray(r.strobe_x[b, k0:], float), np.asarray(r.strobe_v[b, k0:], float)
    scale = max(float(np.abs(np.c_[xs, vs]).max()), 1e-300)
    ends = series.t0 + (np.arange(P) + 1) * series.T
    st, eta, vel = series.modal(ends, block=np.arange(P))
    x, v = _physical(series.prob, st, eta, vel)
    return float(np.abs(np.c_[x - xs[1:], v - vs[1:]]).max()) / scale


def _physical(prob, st, eta, vel):
    """Physical ``x, v`` (K, n) of modal states ``eta, vel`` (K, n) in states ``st`` (K,): ``x`` about each state's
    static equilibrium (a gap's, :class:`plbar.model.Statics`; none without one)."""
    sy, sta = prob.system, prob.statics
    x, v = np.zeros((st.size, sy.n)), np.zeros((st.size, sy.n))
    one, m1, m2 = st == 1, sy.w1.size, sy.w2.size
    x[one, :-1], v[one, :-1] = _each(sy.V1, eta[one, :m1]), _each(sy.V1, vel[one, :m1])
    x[~one], v[~one] = _each(sy.V2, eta[~one, :m2]), _each(sy.V2, vel[~one, :m2])
    if not sta.zero:
        x[one] += sta.x1
        x[~one] += sta.x2
    return x, v


# numpy's stacked matmul makes one BLAS call per row, the same call as for a single vector: a sample's value is
# the same bits whichever other samples are evaluated with it (one plain matrix product would round differently)
def _each(A, X):
    """``A @ x`` for each row ``x`` of ``X``: (K, n) from (n, m) and (K, m)."""
    return np.matmul(A, X[..., None])[..., 0]


def _dots(X, y):
    """``x . y`` for each row ``x`` of ``X`` (K, m) and ``y`` (m,) or each row of ``y`` (K, m): (K,)."""
    return np.matmul(X[:, None, :], np.asarray(y, float)[..., None])[:, 0, 0]
