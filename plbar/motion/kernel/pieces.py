"""Accounts of one piece, compiled: work, ``Psi`` sums, viscous loss, time stuck, contact amplitude.

A *piece* is the part of a segment between two events, or an event and a forcing-period
boundary: its state, its segment (:class:`.data.Segment` ``seg``: its forcing ``seg.ld``, its
start ``seg.ts = tp`` within its forcing period), its length ``tau`` and its modal state at the
start, ``z0[0 | 1]``.  Its accounts, with the closed forms of :mod:`.integrals`:

* the work of the load (every piece: the energy budget of the whole run);
* ``sum_j w_j Psi_j`` (the denominator of ``xi_eq``, Eq. (22)) and ``sum_j Psi_j = int v^T M v dt``
  (mass-normalised modes: the denominator of ``xi_w``), in the recorded window;
* under damping, the viscous loss ``sum_j 2 zeta_j w_j Psi_j`` (modal damping of the Rayleigh ``C``);
* the time stuck and, for a state II piece, the largest ``-x_c`` (:func:`amplitude`: the best of
  :data:`AMP_SAMPLES` samples, refined by Newton on ``v_c = 0``).
"""

from __future__ import annotations

from math import cos, isfinite, sin

from ..model import FREE
from . import data as D
from .closed import flow_at, half, mode_flow
from .integrals import psi, work
from .jit import jit

__all__ = ["AMP_SAMPLES", "amplitude", "gap", "piece_accounts"]

AMP_SAMPLES = 48   #: samples per state II piece before the Newton refinement of its largest gap


@jit
def piece_accounts(md, st, ld, tau, z0, full, damping):
    """``(work, d_eq, d_w, viscous)`` of a piece (``d_eq, d_w`` only where ``full``, viscous only when damped)."""
    modal = md.modal
    hf = half(ld.W, tau)
    wk, d_eq, d_w, visc = 0.0, 0.0, 0.0, 0.0
    for j in range(modal.shape[2]):
        w, f = modal[D.W, st, j], modal[D.F, st, j]
        z = 0.0 if damping is None else damping[st, D.ZETA, j]
        mode, at = D.Mode(w, f, z, modal[D.G, st, j]), D.ModeState(z0[0, j], z0[1, j])
        wk += work(mode, ld, tau, at, damping, hf)
        if full or damping is not None:
            p = psi(mode, ld, tau, at, damping, hf)
            d_eq += p * w
            d_w += p
            visc += p * 2.0 * z * w
    return wk, d_eq, d_w, visc


@jit
def gap(md, seg, u, z0, damping):
    """``-x_c`` and its first two derivatives at ``u`` into a state II piece."""
    modal, ld = md.modal, seg.ld
    hf = half(ld.W, u)
    load = cos(ld.W * (seg.ts + u) - seg.phi)
    g, g1, g2 = 0.0, 0.0, 0.0
    for j in range(modal.shape[2]):
        w, f, c = modal[D.W, FREE, j], modal[D.F, FREE, j], modal[D.C, FREE, j]
        z = 0.0 if damping is None else damping[FREE, D.ZETA, j]
        e, v = mode_flow(D.Mode(w, f, z, modal[D.G, FREE, j]), ld, u, D.ModeState(z0[0, j], z0[1, j]), hf, damping)
        g += c * e
        g1 += c * v
        g2 += c * (f * load + modal[D.G, FREE, j] - w * w * e - 2.0 * z * w * v)
    return g, g1, g2


@jit
def _samples(md, seg, tau, z0, work, damping):
    """``(best, at)``: the largest of the ``AMP_SAMPLES + 1`` equally spaced samples of ``-x_c`` over a state II piece.

    Undamped, the half-angle sines and cosines of the flow are rotated from sample to sample (one sine and cosine
    per mode per piece instead of per sample), in the four rows of ``work``.
    """
    modal, ld, W = md.modal, seg.ld, seg.ld.W
    m = modal.shape[2]
    h = tau / AMP_SAMPLES
    if damping is not None:
        best, at = -1e300, 0.0
        for i in range(AMP_SAMPLES + 1):
            g = gap(md, seg, i * h, z0, damping)[0]
            if g > best:
                best, at = g, i * h
        return best, at
    ca, sa, cr, sr = work[0], work[1], work[2], work[3]
    for j in range(m):
        ca[j], sa[j] = 1.0, 0.0
        cr[j], sr[j] = cos(0.5 * modal[D.W, FREE, j] * h), sin(0.5 * modal[D.W, FREE, j] * h)
    cW, sW, cWr, sWr = 1.0, 0.0, cos(0.5 * W * h), sin(0.5 * W * h)
    best, at = -1e300, 0.0
    for i in range(AMP_SAMPLES + 1):
        g = 0.0
        for j in range(m):
            e, _ = flow_at(D.Mode(modal[D.W, FREE, j], modal[D.F, FREE, j], 0.0, modal[D.G, FREE, j]), ld, i * h,
                           D.ModeState(z0[0, j], z0[1, j]), ca[j], sa[j], D.Half(cW, sW, 2.0 * sW * cW))
            g += modal[D.C, FREE, j] * e
            ca[j], sa[j] = ca[j] * cr[j] - sa[j] * sr[j], sa[j] * cr[j] + ca[j] * sr[j]
        cW, sW = cW * cWr - sW * sWr, sW * cWr + cW * sWr
        if g > best:
            best, at = g, i * h
    return best, at


@jit
def amplitude(md, seg, tau, z0, work, damping):
    """Largest ``-x_c`` over a state II piece: the best of the samples, refined by Newton on ``v_c = 0``.

    Newton steps stay between the neighbours of the best sample; the result is never below the best sample.
    """
    best, ub = _samples(md, seg, tau, z0, work, damping)
    h = tau / AMP_SAMPLES
    lo, hi, x = max(ub - h, 0.0), min(ub + h, tau), ub
    for _ in range(8):
        _, g1, g2 = gap(md, seg, x, z0, damping)
        dx = -g1 / g2 if g2 < 0 else 0.0
        x_new = min(max(x + (dx if isfinite(dx) else 0.0), lo), hi)
        done = not abs(x_new - x) > 1e-15 * tau
        x = x_new
        if done:
            break
    return max(best, gap(md, seg, x, z0, damping)[0])
