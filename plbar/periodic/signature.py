"""Signatures of periodic responses: ``m`` forcing periods, ``k`` stuck/free pairs, which stuck phases have zero dwell.

A periodic response spans ``m`` forcing periods and is a cyclic sequence of
``k >= 1`` pairs, each a stuck phase (state I; its *dwell* ``tau^I_i``) followed
by a free phase (state II, ``tau^II_i > 0``) that ends in a plastic impact
(FORMULATION §8).  A pair of zero dwell is an impact followed at once by the
opening (the reaction just after the impact pulls).  The paper's class is
``m = 1``, one pair of positive dwell: ``"1P"``.

The compact string is ``m`` followed by one letter per pair, ``P`` (positive
dwell) or ``Z`` (zero dwell), written from the rotation that is smallest in
alphabetical order (``P`` before ``Z``): ``"1P"``, ``"1Z"``, ``"2PP"``, ``"2PZ"``, ``"3PPZ"``.

With a coefficient of restitution ``e > 0`` (Newton's impact law, issue 31) an impact
may also be a *rebound*: the contact leaves the wall at once with ``e`` times its
speed, and no stuck phase follows.  A pair that begins with a rebound (instead of a
stuck phase) is the letter ``R``: ``"1R"`` (one rebound per period), ``"2RR"``.  An
impact that sticks (``P``, ``Z``) is then the end of a chattering sequence: its
rebounds are ``R`` pairs, the last one ends in the impact that sticks (the simulator's
accumulation rule, :func:`plbar.motion.kernel.loop.rebound`), so the sequence is
``R...RP``.  The letter of a pair says what follows the impact that ends the pair
before it.  Letters order ``P < R < Z``; a run of three or more rebounds is written
``R`` and its length: ``"1PR9"`` is ``"1PRRRRRRRRR"``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cached_property

from ..errors import InputError

__all__ = ["Signature", "signature", "PAPER", "ZERO_DWELL", "ONE_REBOUND"]

_PATTERN = re.compile(r"^([1-9][0-9]*)((?:[PZ]|R[0-9]*)+)$")
_RUN = re.compile(r"R([0-9]+)")
_COMPACT = re.compile(r"R{3,}")


@dataclass(frozen=True)
class Signature:
    """``m`` forcing periods and the dwell kind of each of the ``k`` pairs (True: positive dwell); ``rebound``
    (True: the pair begins with a rebound, no stuck phase; its dwell is False), all False by default."""

    m: int
    dwell: tuple
    rebound: tuple = None

    def __post_init__(self):
        if int(self.m) != self.m or self.m < 1:
            raise InputError(f"signature m = {self.m!r} must be a positive integer (forcing periods)")
        if not self.dwell or not all(isinstance(d, bool) for d in self.dwell):
            raise InputError(f"signature dwell = {self.dwell!r} must be a non-empty tuple of booleans")
        reb = tuple(False for _ in self.dwell) if self.rebound is None else tuple(self.rebound)
        if len(reb) != len(self.dwell) or not all(isinstance(r, bool) for r in reb) or \
                any(r and d for r, d in zip(reb, self.dwell)):
            raise InputError(f"signature rebound = {self.rebound!r} must be one boolean per pair, False where the "
                             "dwell is positive")
        object.__setattr__(self, "dwell", tuple(self.dwell))
        object.__setattr__(self, "rebound", reb)

    @property
    def letters(self) -> str:
        """One letter per pair: ``P``, ``Z`` or ``R``."""
        return "".join("R" if r else ("P" if d else "Z") for d, r in zip(self.dwell, self.rebound))

    @property
    def rebounds(self) -> int:
        """Pairs that begin with a rebound."""
        return sum(self.rebound)

    @property
    def family(self) -> str:
        """The canonical string with every run of rebounds that ends in a sticking impact (the next pair ``P`` or
        ``Z``: a chattering sequence) written ``C``: ``"1PR9"`` and ``"1PR10"`` are both ``"1PC"``, one family
        whose count of resolved rebounds changes where a rebound's height crosses the simulator's accumulation
        threshold; runs of rebounds without a stick (``"2RR"``) stay as they are."""
        c = self.canonical()
        k, out, i = c.k, [], 0
        letters = c.letters
        while i < k:
            if letters[i] != "R":
                out.append(letters[i])
                i += 1
                continue
            j = i
            while j < k and letters[j] == "R":
                j += 1
            sticks = letters[j % k] != "R" if j < k else letters[0] != "R"
            out.append("C" if sticks else _COMPACT.sub(lambda mt: f"R{len(mt.group(0))}", letters[i:j]))
            i = j
        return f"{c.m}{''.join(out)}"

    def rotated(self, r: int) -> "Signature":
        """The same orbit started ``r`` pairs later."""
        return Signature(self.m, self.dwell[r:] + self.dwell[:r], self.rebound[r:] + self.rebound[:r])

    @property
    def k(self) -> int:
        """Stuck/free pairs (impacts per orbit)."""
        return len(self.dwell)

    @cached_property
    def zero(self) -> int:
        """Pairs of zero dwell."""
        return sum(not d for d in self.dwell)

    @cached_property
    def durations(self) -> int:
        """Unknown durations: the positive dwells and every free phase."""
        return 2 * self.k - self.zero

    def __str__(self) -> str:
        """``m`` and the letters, a run of three or more ``R`` written ``R`` and its length (``"1PR9"``: a chatter of
        nine rebounds before the contact sticks)."""
        return f"{self.m}{_COMPACT.sub(lambda mt: f'R{len(mt.group(0))}', self.letters)}"

    def canonical(self) -> "Signature":
        """The rotation whose string is smallest (the label of the orbit, whatever its start)."""
        return min((self.rotated(i) for i in range(self.k)), key=lambda s: s.letters)

    def parts(self) -> list[tuple[int, int]]:
        """``(m', pairs)`` of every shorter orbit this signature could be a repetition of: ``m'`` a proper divisor of
        ``m`` whose first ``pairs = k m' / m`` pairs, repeated, are the dwell pattern (shortest first)."""
        out = []
        for p in range(1, self.m):
            d = self.m // p
            if self.m % p or self.k % d:
                continue
            n = self.k // d
            if all(self.dwell[i] == self.dwell[i % n] and self.rebound[i] == self.rebound[i % n]
                   for i in range(self.k)):
                out.append((p, n))
        return out

    def repeated(self, times: int) -> "Signature":
        """The same orbit seen over ``times`` times as many periods (a period-doubling seed: ``times = 2``)."""
        return Signature(self.m * times, self.dwell * times, self.rebound * times)

    def head(self, m: int, n: int) -> "Signature":
        """The signature of the first ``n`` pairs over ``m`` periods (a shorter orbit this one repeats)."""
        return Signature(m, self.dwell[:n], self.rebound[:n])


def signature(text) -> Signature:
    """A :class:`Signature` from its string (``"1P"``, ``"2PZ"``) or itself."""
    if isinstance(text, Signature):
        return text
    mt = _PATTERN.match(str(text).strip())
    if not mt:
        raise InputError(f"signature {text!r} must be m and one letter per stuck/free pair: P (positive dwell), "
                         "Z (zero dwell) or R (a rebound, restitution e > 0), e.g. 1P (the paper's class), 1Z, 2PP, "
                         "2PZ, 1R")
    letters = _RUN.sub(lambda r: "R" * int(r.group(1)), mt.group(2))
    if re.search(r"R0", mt.group(2)):
        raise InputError(f"signature {text!r}: a run of rebounds R<n> needs n >= 1")
    return Signature(int(mt.group(1)), tuple(c == "P" for c in letters), tuple(c == "R" for c in letters))


PAPER = Signature(1, (True,))          #: the paper's class
ZERO_DWELL = Signature(1, (False,))    #: one impact per period without a stuck phase
ONE_REBOUND = Signature(1, (False,), (True,))   #: one rebound per period (restitution e > 0)
