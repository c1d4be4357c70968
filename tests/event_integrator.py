"""An event-driven integrator of a two-state structure, written for the tests (not plbar's simulator).

scipy's ``solve_ivp`` (DOP853, rtol 1e-13) on the structure's own equations
``M x'' + K x = q cos(W t - phi) + q_s + r lam``: free (``lam = 0``) while ``u = r . x < d``; held (``lam`` the
force keeping ``u'' = 0``) while the stop pushes (``lam < 0``).  At an impact Newton's law on ``u``:
``v+ = v- - (1 + e) M^-1 r (r . v-) / (r M^-1 r)`` (``e = 0``: plastic, then held).  Each step's dense output is
scanned at 64 points for the switch (solve_ivp's own events see only a step's ends, and a flight that starts at
the stop and returns within one step would go unseen); the crossing is a root of the dense output, and the state
there is integrated to it again from the phase's start.  No chattering (rebounds that accumulate).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

OPENS, IMPACT, REBOUND = 1, 2, 3          # the simulator's event kinds (plbar.motion.kernel.data)
OPTS = dict(rtol=1e-13, atol=1e-14, method="DOP853")


def _phase(rhs, g, t, z, t_end, chunk):
    """Integrate ``rhs`` from ``(t, z)`` until ``g`` first rises through 0 (or ``t_end``): ``(t, z, hit)``."""
    t0, z0 = t, z
    while t < t_end:
        b = min(t + chunk, t_end)
        sol = solve_ivp(rhs, (t, b), z, dense_output=True, **OPTS)
        grid = np.concatenate([sol.t[:1]] + [np.linspace(sol.t[i], sol.t[i + 1], 65)[1:]
                                             for i in range(sol.t.size - 1)])   # a crossing at a chunk's start too
        gv = g(grid, sol.sol(grid))
        up = np.flatnonzero((gv[1:] >= 0) & (gv[:-1] < 0))
        if up.size:
            te = brentq(lambda u, s=sol: g(u, s.sol(u)), grid[up[0]], grid[up[0] + 1], xtol=1e-15, rtol=1e-15)
            return te, solve_ivp(rhs, (t0, te), z0, **OPTS).y[:, -1], True
        t, z = b, sol.y[:, -1]
    return t_end, solve_ivp(rhs, (t0, t_end), z0, **OPTS).y[:, -1], False


def rest(st) -> tuple[np.ndarray, bool]:
    """The static equilibrium of a :class:`plbar.Structure` (physical DOFs) and whether it is free of the stop."""
    K, r, d = st.K, st.contact, st.gap
    q_s = np.zeros(st.n) if st.q_s is None else st.q_s
    Ki = np.linalg.inv(K)
    x0 = Ki @ q_s
    if r @ x0 < d:
        return x0, True
    return Ki @ (q_s + r * ((d - r @ Ki @ q_s) / (r @ Ki @ r))), False


def motion(st, T: float, t_end: float, x0, v0, free: bool, phi: float = 0.0):
    """``(times, kinds, losses, x_end, v_end)`` of a :class:`plbar.Structure` from ``(x0, v0)`` at ``t = 0`` (free
    or held), forced by ``q cos(2 pi t / T - phi)``, to ``t_end``."""
    M, K, r, q, d, e = st.M, st.K, st.contact, st.q, st.gap, st.restitution
    q_s = np.zeros(st.n) if st.q_s is None else st.q_s
    Mi, n, W = np.linalg.inv(M), M.shape[0], 2 * np.pi / T
    rMr = r @ Mi @ r

    def load(t):
        return np.multiply.outer(q, np.cos(W * t - phi)) + (q_s if np.ndim(t) == 0 else q_s[:, None])

    def lam(t, x):                       # the stop's force holding u'' = 0: M x'' = f + r lam (t, x vectorised)
        return -(r @ Mi @ (load(t) - K @ x)) / rMr

    def stuck(t, z):
        return np.concatenate([z[n:], Mi @ (load(t) - K @ z[:n] + r * lam(t, z[:n]))])

    def flight(t, z):
        return np.concatenate([z[n:], Mi @ (load(t) - K @ z[:n])])

    z, t = np.concatenate([np.asarray(x0, float), np.asarray(v0, float)]), 0.0
    times, kinds, losses = [], [], []
    while t < t_end:
        if not free and lam(t, z[:n]) > 0:
            free = True                  # a zero dwell: the reaction pulls at once
            times.append(t), kinds.append(OPENS), losses.append(0.0)
            continue
        if free:
            t, z, hit = _phase(flight, lambda u, y: r @ y[:n] - d, t, z, t_end, T / 4)
        else:
            t, z, hit = _phase(stuck, lambda u, y: lam(u, y[:n]), t, z, t_end, T / 4)
        if not hit:
            break
        if free:
            v = z[n:]
            vp = v - (1.0 + e) * Mi @ r * (r @ v) / rMr
            losses.append(0.5 * v @ M @ v - 0.5 * vp @ M @ vp)
            z = np.concatenate([z[:n], vp])
            times.append(t), kinds.append(REBOUND if e > 0 else IMPACT)
            free = e > 0
        else:
            times.append(t), kinds.append(OPENS), losses.append(0.0)
            free = True
    return np.array(times), np.array(kinds), np.array(losses), z[:n], z[n:]


def assert_same_motion(st, r, T: float, periods: int, b: int = 0, state: int | None = None) -> None:
    """plbar's run ``r`` (trajectory ``b``, from rest over ``periods`` forcing periods ``T``) is this integrator's
    motion of ``st`` from its static equilibrium: the same events (kinds; times to 1e-9), the losses (1e-9), the end
    state (1e-8) and plbar's energy budget closing to 1e-12; ``state`` (0 held, 1 free) asserts the start."""
    assert r.status[b] == 0
    x0, free = rest(st)
    assert state is None or free == (state == 1)
    times, kinds, losses, x_end, _ = motion(st, T, periods * T, x0, np.zeros(st.n), free)
    ev = r.events[r.events["traj"] == b] if "traj" in r.events.dtype.names else r.events
    assert ev.size == times.size > 2 * periods
    assert np.array_equal(ev["kind"], kinds)
    assert np.max(np.abs(ev["time"] - times)) < 1e-9
    assert np.max(np.abs(ev["loss"] - losses)) < 1e-9 * max(losses.max(), 1e-300)
    x_sim = st.physical(r.strobe_x[b, -1])
    assert np.max(np.abs(x_sim - x_end)) < 1e-8 * np.abs(x_end).max()
    assert abs(r.energy_residual[b]) < 1e-12
