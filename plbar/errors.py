"""Error types of plbar.

Every bad input is reported as a :class:`PlbarError` (a ``ValueError``) whose
message names the offending value and the allowed range.  The CLI turns it
into exit code 2 and a single line on stderr.
"""

from __future__ import annotations

__all__ = ["PlbarError", "InputError", "CaseFileError", "OutputExistsError"]


class PlbarError(ValueError):
    """Base class of every error plbar raises on purpose."""


class InputError(PlbarError):
    """A value given to plbar is outside the allowed range."""


class CaseFileError(PlbarError):
    """A case file is malformed (unknown key, wrong type, missing section)."""


class OutputExistsError(PlbarError):
    """The output folder holds results of another run (use ``overwrite``)."""
