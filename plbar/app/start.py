"""A case's given start: the structure's state at ``t = 0`` for its motion (issue 41 item 5, from a case file).

``Case(start_x=X, start_v=V)``, ``[start] x = X`` and ``v = V`` in a case file: each a number (every DOF the same: a
bar displaced or thrown as a whole, a free body dropped from a height, ``x = -h0``) or one number per DOF (the
structure's own DOFs, :attr:`plbar.Case.dofs`: a bar's sorted from the clamp, a structure's as its matrices have
them); the one not given is zeros.  Without either the motion starts at rest, in the static equilibrium
(:func:`plbar.motion.rest`).  The survey simulates every forcing period from the start (its ``rest`` rows: "from the
case's start"; a sweep's first period), and so does the export of its motions; the periodic responses do not
depend on it.  A start past the stop, or at it and moving into it, is refused (:func:`plbar.motion.given`); the
continuum takes its own (:class:`plbar.continuum.Field`).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..util.check import show

__all__ = ["case_start", "start_dict", "start_fields"]


def _vector(name: str, v, n: int):
    """A start's ``x`` or ``v``: a finite number, or ``n`` finite numbers (a tuple); None stays None."""
    if v is None:
        return None
    if isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
        a = float(v)
        if not np.isfinite(a):
            raise InputError(f"{name} = {show(v)} is not allowed; it must be finite")
        return a
    try:
        a = np.asarray(v, float)
    except (TypeError, ValueError):
        a = None
    if a is None or a.ndim != 1 or a.size != n or not np.all(np.isfinite(a)):
        raise InputError(f"{name} = {show(v)} is not allowed; give a number (every DOF) or {n} finite numbers "
                         f"(one per DOF of this structure)")
    return tuple(float(x) for x in a)


def start_fields(case) -> dict:
    """The validated ``start_x, start_v`` of ``case`` (nothing to set where neither is given)."""
    if case.start_x is None and case.start_v is None:
        return {}
    if case.model == "continuum":
        raise InputError("start_x / start_v ([start]) do not apply to model = 'continuum': start its march from a "
                         "field with plbar.continuum.simulate(..., start=plbar.continuum.Field(u, v))")
    n = case.dofs
    return {"start_x": _vector("start_x", case.start_x, n), "start_v": _vector("start_v", case.start_v, n)}


def start_dict(case) -> dict:
    """The start's fields as plain data (:meth:`plbar.Case.to_dict`; none at rest)."""
    if case.start_x is None and case.start_v is None:
        return {}
    plain = lambda v: list(v) if isinstance(v, tuple) else v      # noqa: E731
    return {k: plain(getattr(case, k)) for k in ("start_x", "start_v") if getattr(case, k) is not None}


def case_start(case, prob, B: int):
    """The :class:`plbar.motion.Start` of ``B`` trajectories from the case's start, or None (at rest)."""
    if case.start_x is None and case.start_v is None:
        return None
    from ..model.structure import contact_coordinates
    from ..motion import given
    from ..motion.run import Start

    n = case.dofs
    x, v = (np.broadcast_to(np.asarray(0.0 if a is None else a, float), (n,)) for a in (case.start_x, case.start_v))
    if prob.structure is not None:                # the structure's DOFs -> its contact coordinates (x = B y)
        Bm = contact_coordinates(prob.structure).B
        x, v = np.linalg.solve(Bm, x), np.linalg.solve(Bm, v)
    s = given(prob, x, v)
    return Start(np.repeat(s.state, B), np.repeat(s.eta, B, axis=0), np.repeat(s.vel, B, axis=0))
