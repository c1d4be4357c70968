"""The one shape of a simulation's result (issue 40): :class:`Record`, its status table and its event records.

Every simulator (:func:`plbar.motion.run`, :func:`plbar.check.simulate`, :func:`plbar.continuum.simulate`,
:func:`plbar.continuum.simulate_modal`) returns a subclass of :class:`Record`: the forcing ``T, phi``, a ``status``
per trajectory with its ``message`` read from :data:`STATUS` (as scipy's ``OdeResult``), and the ``events`` as one
numpy structured array of dtype :data:`EVENT` (``r.events["time"]``, ``r.events["kind"]``, ...).  What one simulator
records beyond these is its subclass's own named fields.  The record lives here, in the base layer, because the
independent check simulator (:mod:`plbar.check`) may import only the model and this layer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Record", "EVENT", "STATUS", "OK", "CHATTER", "STALLED", "events", "messages"]

OK, CHATTER, STALLED = 0, 1, 2   #: a trajectory's status (the codes of :data:`plbar.motion.OK` ... too)

#: The one table of status codes and what they mean (``Record.message`` reads it).
STATUS = {
    OK: "ran to the end",
    CHATTER: "a chattering contact (switches ever closer in time: a contact that sticks, or a contact node of a "
             "very small mass: give it more, e.g. a larger end mass)",
    STALLED: "a stall (no progress in time: a stiff contact)",
}

#: One event: its trajectory, absolute time, kind (1 opening, 2 impact; the motion's 3 rebound and 4 the impact
#: that ends a chattering sequence), energy lost, and the contact's velocity where the simulator keeps it (nan
#: where not).
EVENT = np.dtype([("traj", np.int64), ("time", np.float64), ("kind", np.int64), ("loss", np.float64),
                  ("v", np.float64)])


def events(time, kind, loss, traj=None, v=None) -> np.ndarray:
    """The events ``(E,)`` of dtype :data:`EVENT` from their columns (``traj`` 0 and ``v`` nan where not given)."""
    time = np.asarray(time, float).ravel()
    out = np.zeros(time.size, EVENT)
    out["time"], out["kind"], out["loss"] = time, np.asarray(kind).ravel(), np.asarray(loss, float).ravel()
    out["traj"] = 0 if traj is None else np.asarray(traj).ravel()
    out["v"] = np.nan if v is None else np.asarray(v, float).ravel()
    return out


def messages(status) -> list[str]:
    """The :data:`STATUS` message of each code in ``status``."""
    return [STATUS.get(int(s), f"an unknown status {int(s)}") for s in np.atleast_1d(status)]


@dataclass(frozen=True, kw_only=True)
class Record:
    """What every simulator returns (keyword-constructed; a subclass adds its own fields).

    Attributes
    ----------
    T, phi : float or ndarray, shape (B,)
        Forcing period and phase of each trajectory (load ``q cos(2 pi t / T - phi)``); a float where the
        simulator runs one trajectory.
    status : ndarray of int, shape (B,)
        A code of :data:`STATUS` per trajectory (``B = 1`` for one trajectory): 0 ran to the end.
    events : ndarray of dtype EVENT, shape (E,)
        The recorded events of every trajectory, each trajectory's in time order.
    """

    T: float | np.ndarray
    phi: float | np.ndarray
    status: np.ndarray
    events: np.ndarray

    @property
    def success(self) -> bool:
        """Whether every trajectory ran to the end."""
        return bool(np.all(np.asarray(self.status) == OK))

    @property
    def message(self) -> str:
        """What stopped the trajectories (from :data:`STATUS`): one line, :data:`STATUS` ``[OK]`` when none
        stopped."""
        st = np.atleast_1d(self.status)
        bad = np.unique(st[st != OK])
        if not bad.size:
            return STATUS[OK]
        return "; ".join(f"{int(np.sum(st == s))} of {st.size} stopped by {m}" for s, m in zip(bad, messages(bad)))
