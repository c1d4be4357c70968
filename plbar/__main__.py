"""``python -m plbar``: the command line."""

from .cli import entry

entry()
