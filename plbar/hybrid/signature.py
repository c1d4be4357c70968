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
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cached_property

from ..errors import InputError

__all__ = ["Signature", "signature", "PAPER", "ZERO_DWELL"]

_PATTERN = re.compile(r"^([1-9][0-9]*)([PZ]+)$")


@dataclass(frozen=True)
class Signature:
    """``m`` forcing periods and the dwell kind of each of the ``k`` pairs (True: positive dwell)."""

    m: int
    dwell: tuple

    def __post_init__(self):
        if int(self.m) != self.m or self.m < 1:
            raise InputError(f"signature m = {self.m!r} must be a positive integer (forcing periods)")
        if not self.dwell or not all(isinstance(d, bool) for d in self.dwell):
            raise InputError(f"signature dwell = {self.dwell!r} must be a non-empty tuple of booleans")

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
        return f"{self.m}{''.join('P' if d else 'Z' for d in self.dwell)}"

    def canonical(self) -> "Signature":
        """The rotation whose string is smallest (the label of the orbit, whatever its start)."""
        rots = [self.dwell[i:] + self.dwell[:i] for i in range(self.k)]
        return Signature(self.m, min(rots, key=lambda d: "".join("P" if x else "Z" for x in d)))

    def parts(self) -> list[tuple[int, int]]:
        """``(m', pairs)`` of every shorter orbit this signature could be a repetition of: ``m'`` a proper divisor of
        ``m`` whose first ``pairs = k m' / m`` pairs, repeated, are the dwell pattern (shortest first)."""
        out = []
        for p in range(1, self.m):
            d = self.m // p
            if self.m % p or self.k % d:
                continue
            n = self.k // d
            if all(self.dwell[i] == self.dwell[i % n] for i in range(self.k)):
                out.append((p, n))
        return out

    def repeated(self, times: int) -> "Signature":
        """The same orbit seen over ``times`` times as many periods (a period-doubling seed: ``times = 2``)."""
        return Signature(self.m * times, self.dwell * times)


def signature(text) -> Signature:
    """A :class:`Signature` from its string (``"1P"``, ``"2PZ"``) or itself."""
    if isinstance(text, Signature):
        return text
    mt = _PATTERN.match(str(text).strip())
    if not mt:
        raise InputError(f"signature {text!r} must be m and one letter per stuck/free pair: P (positive dwell) or "
                         "Z (zero dwell), e.g. 1P (the paper's class), 1Z, 2PP, 2PZ")
    return Signature(int(mt.group(1)), tuple(c == "P" for c in mt.group(2)))


PAPER = Signature(1, (True,))          #: the paper's class
ZERO_DWELL = Signature(1, (False,))    #: one impact per period without a stuck phase
