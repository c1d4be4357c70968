"""Command line: ``plbar run``, ``mesh``, ``export``, ``render``, ``sweep-loads``, ``refine``, ``figures``, ``survey``.

``main(argv) -> int``; each handler is a thin call into the public API.
Exit codes: 0 ok, 1 failed, 2 bad input (one line on stderr), 130 interrupted.
"""

from __future__ import annotations

import argparse
import gc
import sys
import warnings

from ..errors import NonFiniteError, PlbarError, PlbarWarning
from ..util.progress import message

__all__ = ["main", "entry", "build_parser"]

#: what an interrupted command says: a study (``resumable`` set by its parser) keeps its finished tasks, unless it
#: had none (its KeyboardInterrupt then carries ``kept = False``: it removed its folder)
RESUMABLE = "(finished study tasks are kept; rerun the same command to continue)"
NOT_RESUMABLE = "(no results written)"


class _Parser(argparse.ArgumentParser):
    """argparse with one-line usage errors (exit code 2), like every other bad input."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {_one_line(message)} (see '{self.prog} --help')\n")


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    p = _Parser(prog="plbar", description=(
        "Periodic responses of harmonically forced bars with a unilateral contact, the energy lost at "
        "each plastic impact and the equivalent viscous damping ratio xi_eq."))
    p.add_argument("--version", action="version", version=f"plbar {__version__}")
    sub = p.add_subparsers(dest="cmd", metavar="COMMAND")
    from . import output, run, studies, survey

    run.register(sub)
    output.register(sub)
    studies.register(sub)
    survey.register(sub)
    return p


def main(argv=None) -> int:
    p = build_parser()
    try:
        a = p.parse_args(argv)
    except SystemExit as exc:   # argparse: 2 on bad usage (one line, see _Parser.error), 0 on --help
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    if not getattr(a, "func", None):
        p.print_help()
        return 2
    with warnings.catch_warnings():
        warnings.simplefilter("always", PlbarWarning)
        old_show = warnings.showwarning
        warnings.showwarning = _show_warning(old_show)
        try:
            return a.func(a)
        except NonFiniteError as exc:
            message(f"plbar: failed: {_one_line(exc)}")
            return 1
        except PlbarError as exc:
            message(f"plbar: error: {_one_line(exc)}")
            return 2
        except KeyboardInterrupt as exc:
            kept = getattr(a, "resumable", False) and getattr(exc, "kept", True)   # a study that kept nothing says so
            message("plbar: interrupted " + (RESUMABLE if kept else NOT_RESUMABLE))
            return 130
        except Exception as exc:  # pragma: no cover - reported, not hidden
            message(f"plbar: failed: {type(exc).__name__}: {_one_line(exc)}")
            return 1
        finally:
            warnings.showwarning = old_show


def _one_line(exc) -> str:
    return " ".join(str(exc).split())


def _show_warning(fallback):
    """``warnings.showwarning`` that prints plbar's warnings as one line on stderr (others as Python formats them),
    through :func:`plbar.util.progress.message`."""
    def show(text, category, filename, lineno, file=None, line=None):
        if issubclass(category, PlbarWarning):
            message(f"plbar: warning: {_one_line(text)}")
        elif file is None:                    # stderr: through the one message path (never on a progress bar)
            message(warnings.formatwarning(text, category, filename, lineno, line).rstrip("\n"))
        else:
            fallback(text, category, filename, lineno, file, line)
    return show


def entry() -> None:
    rc = main()
    # The interpreter's last garbage collection walks every object numba and LLVM made (about a second once the
    # kernels are loaded: measured 0.8-1.2 s of a command's wall time, and most of the time between a Ctrl-C and
    # the exit).  Nothing left needs collecting: freeze it all, so the exit skips the walk; atexit handlers (the
    # folder locks) still run.
    gc.freeze()
    sys.exit(rc)
