"""One policy for output folders, and clear messages for missing optional packages.

Every command checks its destination *before* the work (:func:`check_writable`),
clears what it owns there before writing anew (:func:`clear_owned`), so a rerun
never leaves results of another case beside the new ones, and refuses to
replace another case's results unless told to (each command's ``--overwrite``).
"""

from __future__ import annotations

import contextlib
import importlib.util
import shutil
import tempfile
from pathlib import Path

from ..errors import InputError, OutputExistsError

__all__ = ["check_writable", "clear_owned", "require", "refuse_existing", "EXTRAS"]

#: optional package -> the plbar extra that installs it
EXTRAS = {"matplotlib": "plot", "pyvista": "vtk", "h5py": "vtk", "PIL": "vtk", "dask": "dask",
          "distributed": "dask"}


def check_writable(folder) -> Path:
    """Create ``folder`` if needed and prove that a file can be written there; else a one-line InputError."""
    folder = Path(folder)
    for p in (folder, *folder.parents):
        if p.exists():
            if not p.is_dir():
                raise InputError(f"output folder {str(folder)!r} cannot be used: {str(p)!r} is a file; "
                                 "choose another --out")
            break
    try:
        folder.mkdir(parents=True, exist_ok=True)
        for stale in folder.glob(".plbar-probe.*"):      # of a run killed in the middle of this check
            with contextlib.suppress(OSError):
                stale.unlink()
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".plbar-probe."):
            pass
    except OSError as exc:
        raise InputError(f"output folder {str(folder)!r} cannot be written ({exc.strerror or exc}); "
                         "choose another --out") from None
    return folder


def clear_owned(folder, patterns) -> list[Path]:
    """Remove the files and folders matching ``patterns`` (globs) in ``folder``; returns what was removed."""
    folder = Path(folder)
    gone = []
    for pat in patterns:
        for p in sorted(folder.glob(pat)):
            with contextlib.suppress(FileNotFoundError):
                shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()
                gone.append(p)
    return gone


def refuse_existing(paths, what: str) -> None:
    """Raise :class:`OutputExistsError` if any of ``paths`` exists (the caller's ``--overwrite`` lifts it)."""
    there = [str(p) for p in paths if Path(p).exists()]
    if there:
        more = f" and {len(there) - 1} more" if len(there) > 1 else ""
        raise OutputExistsError(f"{what}: {there[0]!r}{more} exists already; pass --overwrite to replace it")


def require(module: str, what: str) -> None:
    """Raise a one-line InputError naming the extra to install if ``module`` is not importable."""
    if importlib.util.find_spec(module) is None:
        extra = EXTRAS.get(module, "all")
        raise InputError(f"{what} needs the optional package {module!r}, which is not installed; "
                         f'install it with: pip install "plbar[{extra}]"')
