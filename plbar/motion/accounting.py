"""Per-period accounts of a batched simulation: ``Psi`` sums, work, time stuck, contact amplitude.

The event loop (:mod:`.integrate`) hands over *pieces*: the part of a
segment between two events or an event and a period boundary, each given by
its state, its start (time within its forcing period) and length, and its
modal state at the start.  Here they are accounted in bulk, with the
closed forms of the periodic solver:

* ``sum_j w_j Psi_j`` (Eq. (21) without ``2 xi``: the denominator of ``xi_eq``, Eq. (22)) and
  ``sum_j Psi_j = int v^T M v dt`` (mass-normalised modes: the denominator of ``xi_w``);
* with inherent damping, the viscous loss ``sum_j 2 zeta_j w_j Psi_j`` (modal damping of the Rayleigh ``C``);
* the work of the load (:func:`plbar.response.segment_work`, independent of the energies; with damping,
  Gauss-Legendre on the exact damped velocity);
* the time spent in state I;
* the largest ``-x_c`` of each state II piece (sampled, then refined by Newton on ``v_c = 0``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..response import psi, segment, segment_work
from ..response.power import work_quadrature_segment
from .margin import taylor
from .model import FREE, STUCK, Padded

__all__ = ["Pieces", "Accounts", "account", "piece_amplitude"]

AMP_SAMPLES = 48   #: samples per state II piece before the Newton refinement of its largest gap
_CHUNK = 500       #: pieces per damped work quadrature (memory)


@dataclass(frozen=True)
class Pieces:
    """A batch of pieces (one row each).

    Attributes
    ----------
    traj, period, state : ndarray of int, shape (P,)
        Trajectory, forcing period (0-based) and state row (``STUCK``/``FREE``).
    tp, tau : ndarray, shape (P,)
        Start within the forcing period, and length.
    eta, vel : ndarray, shape (P, m)
        Modal state at the start.
    """

    traj: np.ndarray
    period: np.ndarray
    state: np.ndarray
    tp: np.ndarray
    tau: np.ndarray
    eta: np.ndarray
    vel: np.ndarray

    def __len__(self) -> int:
        return self.traj.size


@dataclass(frozen=True)
class Accounts:
    """Accounts of a batch of pieces, one value per piece.

    ``d_eq = sum_j w_j Psi_j``, ``d_w = sum_j Psi_j``, ``work``, ``stuck`` (piece length in state I, else 0),
    ``amp`` (largest ``-x_c`` in state II, else 0), ``viscous`` (``sum_j 2 zeta_j w_j Psi_j``, 0 undamped).
    """

    d_eq: np.ndarray
    d_w: np.ndarray
    work: np.ndarray
    stuck: np.ndarray
    amp: np.ndarray
    viscous: np.ndarray


def account(pad: Padded, pcs: Pieces, W: np.ndarray, phi: np.ndarray, full: np.ndarray) -> Accounts:
    """Accounts of ``pcs`` (``W, phi`` per trajectory): the work and viscous loss of every piece, the rest where
    ``full``."""
    Wp, ph = W[pcs.traj][:, None], phi[pcs.traj][:, None]
    w, f = pad.w[pcs.state], pad.f[pcs.state]
    args = (w, f, Wp, pcs.tp[:, None], pcs.tau[:, None], pcs.eta, pcs.vel, np.cos(ph), np.sin(ph))
    n = len(pcs)
    d_eq, d_w, amp, visc = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    if pad.zeta is None:
        work = segment_work(*args).sum(axis=1)
        sel = np.flatnonzero(full)
        if sel.size:
            ps, _ = psi(*(a[sel] for a in args))
            d_eq[sel], d_w[sel] = np.einsum("pj,pj->p", ps, w[sel]), ps.sum(axis=1)
    else:
        zeta = pad.zeta[pcs.state]
        work = np.concatenate([work_quadrature_segment(*(a[i:i + _CHUNK] for a in args), zeta=zeta[i:i + _CHUNK])
                               .sum(axis=1) for i in range(0, n, _CHUNK)]) if n else np.zeros(0)
        ps, _ = psi(*args, zeta=zeta)
        visc = np.einsum("pj,pj->p", ps, 2.0 * zeta * w)
        d_eq[full], d_w[full] = np.einsum("pj,pj->p", ps, w)[full], ps.sum(axis=1)[full]
    sel = np.flatnonzero(full & (pcs.state == FREE) & (pcs.tau > 0))
    if sel.size:
        amp[sel] = piece_amplitude(pad, _take(pcs, sel), W, phi)
    return Accounts(d_eq, d_w, work, np.where(pcs.state == STUCK, pcs.tau, 0.0), amp, visc)


def _take(pcs: Pieces, sel) -> Pieces:
    return Pieces(*(getattr(pcs, k)[sel] for k in ("traj", "period", "state", "tp", "tau", "eta", "vel")))


def _gap(pad: Padded, pcs: Pieces, W, phi, u, second: bool = False):
    """``-x_c`` and its first (and second) derivative on state II pieces at local times ``u`` (P, K)."""
    Wp, ph = W[pcs.traj][:, None, None], phi[pcs.traj][:, None, None]
    zeta = None if pad.zeta is None else pad.zeta[FREE]
    eta, vel = segment(pad.w[FREE], pad.f[FREE], Wp, pcs.tp[:, None, None], u[..., None], pcs.eta[:, None, :],
                       pcs.vel[:, None, :], np.cos(ph), np.sin(ph), zeta=zeta)
    P, K, m = eta.shape
    rows = P * K
    d, _, _, Om = taylor(np.broadcast_to(pad.c[FREE], (rows, m)), np.zeros(rows), np.broadcast_to(pad.w[FREE], (rows, m)),
                         np.broadcast_to(pad.f[FREE], (rows, m)), eta.reshape(-1, m), vel.reshape(-1, m),
                         np.repeat(W[pcs.traj], K), (pcs.tp[:, None] + u).ravel(), np.repeat(phi[pcs.traj], K),
                         np.zeros(rows), 2, None if zeta is None else np.broadcast_to(zeta, (rows, m)))
    out = (d[0].reshape(P, K), (d[1] * Om).reshape(P, K))
    return out + ((d[2] * Om * Om).reshape(P, K),) if second else out


def piece_amplitude(pad: Padded, pcs: Pieces, W, phi, newton: int = 8) -> np.ndarray:
    """Largest ``-x_c`` over each state II piece: the best of ``AMP_SAMPLES`` samples, refined by Newton on ``v_c = 0``.

    Newton steps stay between the neighbours of the best sample; the result is
    never below the best sample.
    """
    frac = np.linspace(0.0, 1.0, AMP_SAMPLES + 1)
    u = pcs.tau[:, None] * frac
    g, _ = _gap(pad, pcs, W, phi, u)
    k = np.argmax(g, axis=1)
    rows = np.arange(len(pcs))
    best = g[rows, k]
    h = pcs.tau / AMP_SAMPLES
    lo, hi = np.maximum(u[rows, k] - h, 0.0), np.minimum(u[rows, k] + h, pcs.tau)
    x = u[rows, k]
    for _ in range(newton):
        _, g1, g2 = _gap(pad, pcs, W, phi, x[:, None], second=True)
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = np.where(g2[:, 0] < 0, -g1[:, 0] / g2[:, 0], 0.0)
        x = np.clip(x + np.nan_to_num(dx), lo, hi)
    gx, _ = _gap(pad, pcs, W, phi, x[:, None])
    return np.maximum(best, gx[:, 0])
