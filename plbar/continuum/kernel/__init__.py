"""The compiled continuum kernels (numba): the end's closed-form motion fed by the delay line, and its record.

One kernel, :func:`~.march.march`, does the whole march; its pieces are compiled into it (:mod:`.jit`: the entry
points are cached on disk, keyed by every source of the package): :mod:`.end` the closed forms and events,
:mod:`.merge` the merge, :mod:`.march` the steps; :mod:`.fields` and :mod:`.accounts` evaluate the record for the
accounts.

* **The end over a piece** ``t in [ta, ta + h]``: the incoming invariant is ``w_in = l0 + l1 tau + C cos(omega t) +
  D sin(omega t)`` (``tau = t - ta``) and the end obeys ``m v' = -Z v + g(t)``, ``g = Z w_in + F_L`` (``F_L`` the load
  if it acts on the end), ``u' = v`` while free; ``u = v = 0`` and the wall force ``r = -g <= 0`` while stuck
  (FORMULATION §3).  Free, ``v = l0p + l1p tau + a cos + b sin + K exp(-lam tau)`` (:func:`.end.free`, a 9-tuple).
* **Events**: opening (``g`` turns negative) and the return to the wall (``u`` reaches 0 from below) are sign
  changes on :data:`SAMPLES` points of the piece, plus the extrema between samples (a dip of ``g`` below zero, a
  return of ``u`` between samples shows as a ``+ -`` change of ``v``), located by Brent's method (the algorithm
  of scipy's ``brentq``, to 1e-15) and, for the dips, golden-section minimisation.
* **The record** ``w_out`` per piece: linear (``a0`` at ``tau0``, ``a1`` at ``tau1``, local times of grid step
  ``k``) plus ``C cos + D sin``, and ``jump``: whether ``w_out`` jumps at the piece's start.  Stuck, ``w_out = -w_in``;
  free, ``w_out = 2 v - w_in`` whose transient ``2 K exp(-lam tau)`` is stored as its L2 projection on linear
  functions scaled to keep ``int w_out^2`` (:func:`.end.stored_line`).
* **The merge**: when a grid step is done, its pieces between jumps (joined at period cuts, load-delay points,
  openings, the delayed pieces' kinks) are merged into one piece per jump-free run (:func:`.merge.merge_run`): the
  harmonic part is the run's length-weighted mean, the rest is projected (L2, Gauss-Legendre on every piece) on
  one linear function, scaled so that ``int w_out^2`` over the run is kept exactly.  Jumps (impacts: ``w_out``
  jumps by ``-2 v``; the load's arrival from rest; the jumps carried in by the delay line) stay breakpoints.  So a
  step holds one piece plus one per jump in it, and the delay line still conserves energy to round-off.

The arrays grow by doubling; nothing else is allocated in the loop.  numba is imported only here (with
:mod:`plbar.continuum`, which ``import plbar`` does not import).
"""

from .end import SAMPLES
from .march import IMPACT, MAX_EVENTS_PER_STEP, OPENING, march

__all__ = ["SAMPLES", "MAX_EVENTS_PER_STEP", "OPENING", "IMPACT", "march"]
