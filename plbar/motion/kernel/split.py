"""A certified step from the low modes alone: the fast modes bounded by their free-vibration amplitude.

Above a split index ``J`` every mode is fast (``w_j >= 2 W``).  Write its motion as
``eta_j = p_j + h_j``: ``p_j = Re(P_j e^{i (W t - phi)})`` the steady response to the load,
``P_j = f_j / (w_j^2 - W^2 + 2 i zeta_j w_j W)``, and ``h_j`` a free (damped) oscillation whose
amplitude ``A_j = |(w_j h_j, h_j')|`` never grows (its energy is kept, or taken by damping).  So
at every later time

``|sum_{j>=J} c_j h_j + cv_j h_j'| <= E_J = sum_{j>=J} (|c_j| / w_j + |cv_j|) A_j``,

and the margin is bounded below by that of the low modes, with the fast modes' steady part added
to the load term, less ``E_J``:

``g(t + u) >= g_J(t + u) - E_J``,
``g_J = sum_{j<J} (c_j eta_j + cv_j eta_j') + R_c cos(W t - phi) + R_s sin(W t - phi)``.

The Taylor model of ``g_J`` (:func:`plbar.motion.kernel.certify.taylor`) is scaled by the fastest
*low* mode instead of the fastest mode.  Where the fast modes carry little (a bar's end moves
smoothly between the fronts an impact sends), the certified step is many times longer: an FE bar
of 256 elements carries about 1e-3 of its margin above its 16th mode.  ``J`` is the smallest
index whose ``E_J`` is at most a quarter of the margin.
"""

from __future__ import annotations

from math import sqrt

from . import data as D
from .data import SPLIT_MIN
from .certify import step_from, taylor
from .jit import jit

__all__ = ["SPLIT_MIN", "SPLIT_ORDER", "particular", "split_step"]

SPLIT_ORDER = 16   #: order of the split model (its low modes are slow: a higher order certifies longer steps)

@jit
def particular(md, damping, W, P, fast):
    """``P[state, 0 | 1, j]`` (real, imaginary part of the steady amplitude) and ``fast[state]``: the first index
    from which every mode is fast (``w_j >= 2 W``), for a trajectory of forcing frequency ``W``."""
    modal = md.modal
    m = modal.shape[2]
    for st in range(2):
        fast[st] = m
        for j in range(m - 1, -1, -1):
            inert = modal[D.F, st, j] == 0 and modal[D.C, st, j] == 0 and (damping is None or
                                                                           damping[st, D.CV, j] == 0)
            if modal[D.W, st, j] < 2.0 * W and not inert:    # (the padding mode of state I is inert)
                break
            fast[st] = j
        for j in range(m):
            w, f = modal[D.W, st, j], modal[D.F, st, j]
            a = 0.0 if damping is None else damping[st, D.ZETA, j] * w
            den = complex(w * w - W * W, 2.0 * a * W)
            p = f / den if den != 0 else 0j
            P[st, 0, j], P[st, 1, j] = p.real, p.imag


@jit
def _free(c, cvj, w, pr, pi, load, eta, vel):
    """``(|c| / w + |cv|) A``: the bound of a fast mode's free part in the margin (``A`` its free amplitude; ``pr, pi``
    its steady amplitude, ``load`` the :class:`.data.LoadTerm` at the point)."""
    W, ct, st = load.W, load.ca, load.sa
    h = eta - (pr * ct - pi * st)
    hv = vel + W * (pr * st + pi * ct)
    return (abs(c) / w + abs(cvj)) * sqrt((w * h) ** 2 + hv * hv)


@jit
def split_step(md, st, W, ct, s_t, cap, wk, damping):
    """A certified step (unscaled) from the split model of order :data:`SPLIT_ORDER`, or -1 where it does not pay
    (see the module docstring), at the point ``wk.e, wk.v``, ``ct, s_t = cos, sin(W t - phi)`` there
    (:class:`.data.Work`: ``wk.P, wk.fast`` from :func:`particular`)."""
    modal, margin, K, eta, vel = md.modal, md.margin, SPLIT_ORDER, wk.e, wk.v
    d, scale, amp, P, fast = wk.d, wk.scale, wk.amp, wk.P, wk.fast
    c, w, f = modal[D.C, st], modal[D.W, st], modal[D.F, st]
    m = w.size
    g0 = margin[D.G0, st]
    g = margin[D.RQ, st] * ct + g0
    at = D.LoadTerm(W, ct, s_t, margin[D.RQ, st], 0.0, g0)
    for j in range(m):
        cvj = 0.0 if damping is None else damping[st, D.CV, j]
        g += c[j] * eta[j] + cvj * vel[j]
        amp[j] = _free(c[j], cvj, w[j], P[st, 0, j], P[st, 1, j], at, eta[j], vel[j])
    J, tail = m, 0.0
    for j in range(m - 1, max(fast[st], 1) - 1, -1):
        if tail + amp[j] > 0.25 * g:
            break
        tail += amp[j]
        J = j
    top, low = 0.0, 0.0
    for j in range(m):
        top = max(top, w[j])
        if j < J:
            low = max(low, w[j])
    if J == m or 2.0 * max(low, W) > top:
        return -1.0
    Rc, Rs = margin[D.RQ, st], 0.0
    for j in range(J, m):
        cvj = 0.0 if damping is None else damping[st, D.CV, j]
        Rc += c[j] * P[st, 0, j] - cvj * W * P[st, 1, j]
        Rs += -c[j] * P[st, 1, j] - cvj * W * P[st, 0, j]
    low, load = D.Modes(w[:J], f[:J], c[:J], modal[D.G, st, :J]), D.LoadTerm(W, ct, s_t, Rc, Rs, g0)
    if damping is None:
        rem, Om = taylor(low, None, eta[:J], vel[:J], load, cap, K, d, scale)
    else:
        rem, Om = taylor(low, D.Damping(damping[st, D.ZETA, :J], damping[st, D.CV, :J]), eta[:J], vel[:J], load, cap,
                         K, d, scale)
    lead = d[0] - tail
    if not lead > 0:
        return -1.0
    v = step_from(d, K, 0, lead, rem, Om * cap, wk.taylor)
    return v / Om if v > 0 else -1.0
