"""The admissibility margin of a segment, its Taylor expansion and a certified remainder (pure functions).

In either state the margin is ``g(t) = c . eta(t) + rq cos(W t - phi)``
(``-R`` in state I, Eq. (4); ``-x_c`` in state II, Eq. (5)): the state holds
while ``g >= 0``.  Its derivatives follow from the modal equation
``eta'' = f cos(W t - phi) - w^2 eta`` (Eq. (1) in modal form):

``eta^(k) = f W^(k-2) cos(W t - phi + (k-2) pi/2) - w^2 eta^(k-2)``.

**Remainder bound.**  For each mode the amplitude ``a = |(w eta, etadot)|``
obeys ``|da/dt| <= |f|`` (the load's power per unit velocity), so over a
step of length ``s`` it stays below ``a + |f| s``; then ``|eta| <= a / w``,
``|etadot| <= a`` and, by the same recursion, ``|eta^(k)| <= |f| W^(k-2) +
w^2 |eta^(k-2)|``.  Summed with the weights ``|c|`` this bounds
``|g^(k)|`` over the whole step.  The bound ignores every cancellation
between modes, so it is used only for the remainder of a Taylor expansion of
high order (:mod:`.events`), where it is multiplied by ``s^(K+1) / (K+1)!``.

Everything is scaled by ``Om = max(w_max, W)`` (``g^(k) / Om^k``), so that
high orders stay finite.
"""

from __future__ import annotations

import numpy as np

__all__ = ["margin", "taylor"]


def margin(c, rq, eta, vel, W, t, phi):
    """``g`` and ``g'`` of a batch (rows) at absolute times ``t`` (undamped margins; :func:`taylor` takes damping).

    Parameters
    ----------
    c : ndarray, shape (B, m)
        Margin weights of each row's state.
    rq : ndarray, shape (B,)
        Load term of each row's margin.
    eta, vel : ndarray, shape (B, m)
        Modal displacements and velocities at ``t``.
    W, t, phi : ndarray, shape (B,)

    Returns
    -------
    g, g1 : ndarray, shape (B,)
    """
    arg = W * t - phi
    g = np.einsum("bj,bj->b", c, eta) + rq * np.cos(arg)
    g1 = np.einsum("bj,bj->b", c, vel) - rq * W * np.sin(arg)
    return g, g1


def taylor(c, rq, w, f, eta, vel, W, t, phi, s, K: int, zeta=None, cv=None):
    """Scaled derivatives ``g^(k) / Om^k`` (``k = 0 .. K``) and the bound of ``|g^(K+1)| / Om^(K+1)`` over a step.

    Parameters
    ----------
    c, w, f, eta, vel : ndarray, shape (B, m)
        Margin weights, frequencies, modal loads, modal state at ``t``.
    rq, W, t, phi : ndarray, shape (B,)
    s : ndarray, shape (B,)
        Step length over which the remainder bound must hold.
    K : int
        Highest derivative.
    zeta, cv : ndarray, shape (B, m), optional
        Inherent damping: the modal ratios (``eta'' = f cos - w^2 eta - 2 zeta w eta'``) and the margin's
        weights on the modal velocities (``g = c . eta + cv . eta' + rq cos``; the damper's share of the
        reaction).  The amplitude bound holds as it is (damping only takes energy out).

    Returns
    -------
    d : ndarray, shape (K + 1, B)
        ``g^(k)(t) / Om^k``.
    rem : ndarray, shape (B,)
        Bound of ``|g^(K+1)(t + u)| / Om^(K+1)`` for ``0 <= u <= s``.
    scale : ndarray, shape (K + 1, B)
        The size of the terms that make ``g^(k)`` (scaled; through the recursion, so that a derivative that
        cancels to round-off is seen as such), for round-off tests.
    Om : ndarray, shape (B,)
    """
    Om = np.maximum(w.max(axis=1), W)
    wr2 = (w / Om[:, None]) ** 2
    Wr = W / Om
    arg = W * t - phi
    ac, af, arq = np.abs(c), np.abs(f), np.abs(rq)
    amp = np.hypot(w * eta, vel) + af * s[:, None]
    e = [eta, vel / Om[:, None]]
    mag = [np.abs(eta), np.abs(vel) / Om[:, None]]       # size of the terms of each e[k]: its round-off level
    b = [amp / w, amp / Om[:, None]]
    load = f / (Om ** 2)[:, None]
    damp = None if zeta is None else 2.0 * zeta * w / Om[:, None]
    top = K + (2 if cv is not None else 1)
    for k in range(2, top + 1):
        Wk = Wr ** (k - 2)
        if k < top:
            lk = load * (Wk * np.cos(arg + 0.5 * np.pi * (k - 2)))[:, None]
            e.append(lk - wr2 * e[k - 2] - (0.0 if damp is None else damp * e[k - 1]))
            mag.append(np.abs(lk) + wr2 * mag[k - 2] + (0.0 if damp is None else damp * mag[k - 1]))
        b.append(np.abs(load) * Wk[:, None] + wr2 * b[k - 2] + (0.0 if damp is None else damp * b[k - 1]))
    ks = np.arange(K + 1)[:, None]
    forced = rq * Wr ** ks * np.cos(arg + 0.5 * np.pi * ks)
    d = np.einsum("bj,kbj->kb", c, np.stack(e[:K + 1]))
    scale = np.einsum("bj,kbj->kb", ac, np.stack(mag[:K + 1])) + np.abs(forced)
    rem = np.einsum("bj,bj->b", ac, b[K + 1]) + arq * Wr ** (K + 1)
    if cv is not None:                                    # g^(k) also holds cv . eta^(k+1)
        cvs = cv * Om[:, None]
        d = d + np.einsum("bj,kbj->kb", cvs, np.stack(e[1:K + 2]))
        scale = scale + np.einsum("bj,kbj->kb", np.abs(cvs), np.stack(mag[1:K + 2]))
        rem = rem + np.einsum("bj,bj->b", np.abs(cvs), b[K + 2])
    d = d + forced
    return d, rem, scale, Om
