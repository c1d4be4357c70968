"""The styles every figure shares: one (colour, marker) per contact signature, and the units of the axes.

:func:`signature_styles` gives each signature of a figure its colour and marker: a
signature's own pair comes from its place among all signatures (the same in every figure), and
two signatures of one figure never share both (a later one that would takes the next free pair).  The
paper's class ``1P`` keeps the paper's blue circle.  :func:`unit_note` says in which
units a bar's numbers are (``m = k = 1`` for the chain, ``L = c = 1`` for an FE bar).
"""

from __future__ import annotations

import zlib

import numpy as np

__all__ = ["PAPER_SIGNATURE", "PAPER_STYLE", "SIG_COLORS", "SIG_MARKS", "signature_styles", "unit_note", "with_units"]

PAPER_SIGNATURE = "1P"                     #: the paper's class: one stuck phase, one impact per period
PAPER_STYLE = ("tab:blue", "o")            #: its colour and marker (unstable points: red crosses)
#: colours and markers of the other signatures; 12 colours against 13 markers (coprime): the pairs
#: ``(SIG_COLORS[k % 12], SIG_MARKS[k % 13])``, k < 156, are all different
SIG_COLORS = ("tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:cyan", "tab:olive", "tab:pink", "gold",
              "teal", "darkslateblue", "peru", "olive")
SIG_MARKS = ("s", "D", "^", "v", "P", "*", "h", "<", ">", "p", "X", "d", "H")
_PAIRS = len(SIG_COLORS) * len(SIG_MARKS)


def _pair(k: int) -> tuple[str, str]:
    return SIG_COLORS[k % len(SIG_COLORS)], SIG_MARKS[k % len(SIG_MARKS)]


def _number(label: str) -> int:
    """The place of a signature ``<m><word>`` (``m <= 8``, word of ``P`` and ``Z``) when ordered by the word's
    length, then the word (``P`` before ``Z``), then ``m``: short signatures come first and never share one; any
    other label by its checksum."""
    m, word = label[:1], label[1:]
    if not (m.isdigit() and 1 <= int(m) <= 8 and word and set(word) <= {"P", "Z"}):
        return zlib.crc32(label.encode())
    rank = 2 ** len(word) - 2 + int(word.replace("P", "0").replace("Z", "1"), 2)
    return 8 * rank + int(m) - 1


def signature_styles(labels) -> dict[str, tuple[str, str]]:
    """``label -> (colour, marker)`` of the signatures drawn in one figure, no two alike.

    Parameters
    ----------
    labels : iterable of str
        Signatures (``"1PZ"``, ``"2ZZZ"``, ...), repeats allowed.

    Returns
    -------
    dict
        In the order of ``labels``.  ``"1P"`` gets :data:`PAPER_STYLE`; any other signature the pair of its
        place among all signatures (:func:`_number`, modulo the 156 pairs), or, if a signature before it in that
        order took the pair, the next free one: the signatures up to three letters after ``m`` have their own pair
        in every figure.  Beyond 156 signatures in one figure pairs repeat.
    """
    labels = list(dict.fromkeys(labels))
    out, used = {}, set()
    for lab in sorted(labels, key=lambda x: (_number(x), x)):
        if lab == PAPER_SIGNATURE:
            out[lab] = PAPER_STYLE
            continue
        k = _number(lab) % _PAIRS
        k = next(((k + j) % _PAIRS for j in range(_PAIRS) if (k + j) % _PAIRS not in used), k)
        used.add(k)
        out[lab] = _pair(k)
    return {lab: out[lab] for lab in labels}


def unit_note(bar) -> str:
    """The units of a bar's numbers: ``"m = k = 1"`` (chain), ``"L = c = 1"`` (FE bar), or their values
    (``"L = 3, c = 3,536"``: the length as given, the wave speed to 4 significant digits).

    Parameters
    ----------
    bar : plbar.model.Bar or None
        None (no bar known): ``""``.  The chain (``paper_chain``: masses ``m = rhoA``, springs ``k = EA``; time in
        units of ``sqrt(m/k)``)
        or an FE bar (length ``L``, wave speed ``c = sqrt(EA/rhoA)``; time in units of ``L/c``).
    """
    if bar is None:
        return ""
    EA, rhoA = np.atleast_1d(np.asarray(bar.EA, float)), np.atleast_1d(np.asarray(bar.rhoA, float))
    if bar.paper_chain:
        m, k = float(rhoA[0]), float(EA[0])
        return "m = k = 1" if m == k == 1 else f"m = {m:g}, k = {k:g}"
    L = float(bar.nodes[-1])
    c = np.sqrt(EA / rhoA)
    if np.ptp(c) > 0:
        return f"L = {L:g}, c = sqrt(EA/rhoA) per element"
    c = float(c[0])
    return "L = c = 1" if L == c == 1 else f"L = {L:g}, c = {c:,.4g}"     # c: a square root, to 4 digits


def with_units(label: str, note: str) -> str:
    """An axis label with its units: ``"forcing period T (m = k = 1)"``, ``"xi_eq (Eq. 22; dimensionless)"``
    (a label ending in a parenthesis gets the note inside it); ``note`` empty: the label itself."""
    if not note:
        return label
    return f"{label[:-1]}; {note})" if label.endswith(")") else f"{label} ({note})"
