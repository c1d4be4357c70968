"""The command line (``plbar``): ``main(argv) -> int`` and the console entry point; nothing imports it."""

from .main import build_parser, entry, main

__all__ = ["build_parser", "entry", "main"]
