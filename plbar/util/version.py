"""The version of plbar (one definition: ``plbar.__version__``, recorded in every result and owner marker)."""

__all__ = ["__version__"]

__version__ = "0.1.0"
