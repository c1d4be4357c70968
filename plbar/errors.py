"""Error and warning types of plbar.

Every bad input is reported as a :class:`PlbarError` (a ``ValueError``) whose
message names the offending value and the allowed range.  The CLI turns it
into exit code 2 and a single line on stderr.  A result that is not finite
(a solver failure, never a bad input) is a :class:`NonFiniteError`: it is
refused before anything is written, and the CLI exits with code 1.

Warnings (:class:`PlbarWarning` and subclasses, issued with
:func:`warnings.warn`) flag inputs that are allowed but likely to give poor
results, such as a scan grid too coarse to resolve the branches.
"""

from __future__ import annotations

__all__ = ["PlbarError", "InputError", "CaseFileError", "OutputExistsError", "NonFiniteError",
           "PlbarWarning", "CoarseGridWarning", "TruncationWarning", "LargeOutputWarning"]


class PlbarError(ValueError):
    """Base class of every error plbar raises on purpose."""


class InputError(PlbarError):
    """A value given to plbar is outside the allowed range."""


class CaseFileError(PlbarError):
    """A case file is malformed (unknown key, wrong type, missing section)."""


class OutputExistsError(PlbarError):
    """The output folder holds results of another run (use ``overwrite``)."""


class NonFiniteError(PlbarError):
    """A computed result is nan or infinite; it is never written to disk."""


class PlbarWarning(UserWarning):
    """Base class of the warnings plbar issues."""


class CoarseGridWarning(PlbarWarning):
    """The scan grid (or a branch found on it) is too coarse to resolve the paths well."""


class TruncationWarning(PlbarWarning):
    """``Delta_PL`` and ``xi_eq`` of a modally truncated model: the impact loses the energy outside the kept modes."""


class LargeOutputWarning(PlbarWarning):
    """A result table is about to be very large (the warning names the options that make it smaller)."""
