"""One ownership rule for output folders, and clear messages for missing optional packages.

Every command writes into its ``--out`` folder a small marker, ``.plbar-owner.json``::

    {"command": "run", "fingerprint": "3f0c9a1e5b7d2c44", "owned": ["paths.csv", "summary.json", "vtk", ...],
     "plbar": "0.1.0"}

naming the command, a fingerprint of the case (or study) it wrote, and the files it owns there (glob
patterns).  :func:`claim_folder` is the one rule, for every command:

* a folder without a marker (and without the ``summary.json`` / ``study.json`` by which plbar results were
  recognised before markers existed) is claimed;
* a folder of the same command and fingerprint is the command's own (a rerun, a resumed study);
* a command named in ``joins`` may add its files to a folder of the same fingerprint (``export`` and
  ``render`` into the folder of the ``run`` they come from): they join its owned list;
* anything else (another command, another case) is refused with one line, unless ``overwrite``: then what
  the old owner owned is removed first, and nothing else in the folder is touched.

:func:`check_folder` applies the rule without writing results (call it before a long solve; ``Claim.take`` when
the results are ready).  A claim also holds the folder's lock, ``.plbar-lock`` (written aside and hard-linked into
place: atomic, holding the pid and host of its process), until the claim is released or the process exits: a second
command on the same folder while the first runs, of another case or of the same one, is refused with one line (it
would otherwise write over the first, or be lost).  Claims of one process on one folder share its lock.  A lock whose
process is dead (killed) is stale and taken over; one of another host is respected (delete the file by hand if that
host's command is gone).  Used as a context manager, a claim is undone when the command fails or is interrupted
before writing any of its files: no marker and no empty folder are left behind; a resumable study calls
``Claim.abandon(finished)`` when it fails before finishing anything.

A new command needs one line (a resumable study resumes when the fingerprint is the same)::

    claim = claim_folder(out, "survey", fingerprint(definition), ("survey.csv", "tasks", ...), overwrite)
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import importlib.util
import json
import os
import shutil
import socket
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError, OutputExistsError
from .files import write_json
from .version import __version__

__all__ = ["check_creatable", "MARKER", "LOCK", "Owner", "Claim", "fingerprint", "read_owner", "check_folder",
           "claim_folder", "check_writable", "clear_owned", "require", "EXTRAS"]

#: the owner marker every command writes into its output folder
MARKER = ".plbar-owner.json"
#: the lock a claim holds on its folder while its command runs
LOCK = ".plbar-lock"
#: files by which plbar results were recognised before markers existed (a folder holding one has an unknown owner)
LEGACY = ("summary.json", "study.json")

#: optional package -> the plbar extra that installs it
EXTRAS = {"matplotlib": "plot", "pyvista": "vtk", "h5py": "vtk", "PIL": "vtk", "dask": "dask",
          "distributed": "dask"}


def fingerprint(data) -> str:
    """A 16-hex-digit fingerprint of JSON-able ``data`` (canonical JSON, sha256): the identity of a case or study."""
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Owner:
    """The content of a folder's marker: which command wrote it, for which case, and what it owns there."""

    command: str
    fingerprint: str
    owned: tuple[str, ...] = ()
    version: str = __version__

    def as_dict(self) -> dict:
        return {"command": self.command, "fingerprint": self.fingerprint, "owned": list(self.owned),
                "plbar": self.version}


def read_owner(folder) -> Owner | None:
    """The owner recorded in ``folder`` (None without a marker; an unreadable marker is an unknown owner)."""
    path = Path(folder) / MARKER
    if not path.exists():
        return None
    try:
        d = json.loads(path.read_text())
        return Owner(str(d["command"]), str(d["fingerprint"]), tuple(str(p) for p in d.get("owned", ())),
                     str(d.get("plbar", "")))
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return Owner("unknown", "", ())


def _matches(folder: Path, patterns) -> list[Path]:
    return [p for pat in patterns for p in sorted(folder.glob(pat))]


@dataclass
class Claim:
    """A command's claim on its output folder (see :func:`check_folder`); ``take`` makes it the owner.

    ``previous`` is the owner found (None: none), ``replace`` whether it is removed at ``take`` (``overwrite``),
    ``created`` the folders made to prove the folder writable (removed again if the claim is undone empty),
    ``lock`` the folder's lock if this claim took it (None: another claim of this process holds it).
    """

    folder: Path
    owner: Owner
    previous: Owner | None
    replace: bool
    created: list[Path] = field(default_factory=list)
    taken: bool = False
    lock: Path | None = None

    def take(self) -> "Claim":
        """Remove what a replaced owner owned, then write the marker (with the owned patterns of a joined owner)."""
        if self.taken:
            return self
        prev, new = self.previous, self.owner
        if self.replace:
            clear_owned(self.folder, (prev.owned if prev else ()) + new.owned + (LEGACY if prev is None else ()))
            prev = None
        if prev is not None:          # the same owner, or one this command joins: keep its name, add the patterns
            new = Owner(prev.command, prev.fingerprint, tuple(dict.fromkeys(prev.owned + new.owned)))
        clear_owned(self.folder, (".plbar-owner.*.part.json",))          # of a marker write that was killed
        write_json(self.folder / MARKER, new.as_dict())
        self.taken = True
        return self

    def wrote_nothing(self) -> bool:
        """No file this command owns exists in the folder (only, perhaps, the marker)."""
        return not _matches(self.folder, self.owner.owned)

    def unlock(self) -> None:
        """Release the folder's lock (if this claim took it): the command is done with the folder."""
        if self.lock is not None:
            _unlock(self.lock)
            self.lock = None

    def release(self) -> None:
        """Undo the claim: remove the marker it wrote (never another owner's), its lock and the folders it created,
        if empty."""
        if self.taken and (self.previous is None or self.replace):
            with contextlib.suppress(OSError):
                (self.folder / MARKER).unlink()
        self.unlock()
        for d in reversed(self.created):
            with contextlib.suppress(OSError):
                d.rmdir()              # only an empty folder goes

    def abandon(self, finished=(), exc: BaseException | None = None) -> bool:
        """After a failure: unless a file matching ``finished`` (globs: finished work a rerun resumes) exists, remove
        what this command owns here and undo the claim, so that nothing blocks a corrected rerun.  True if undone;
        then an interrupt ``exc`` (KeyboardInterrupt) is marked ``kept = False``, and the command line says that
        nothing was kept."""
        if _matches(self.folder, finished):
            return False
        clear_owned(self.folder, self.owner.owned)
        self.release()
        if isinstance(exc, KeyboardInterrupt):
            exc.kept = False
        return True

    def __enter__(self) -> "Claim":
        return self

    def __exit__(self, kind, exc, tb) -> bool:
        if kind is not None and (not self.taken or self.wrote_nothing()):
            self.release()
        self.unlock()
        return False


#: the locks this process holds (released at its exit, if a command did not release them before)
_HELD: set[Path] = set()


def _lock_holder(lock: Path) -> dict | None:
    """The ``{"pid", "host"}`` recorded in ``lock`` (None if it is gone; ``{}`` if unreadable: by hand)."""
    try:
        return json.loads(lock.read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError):
        return {}


def _alive(holder: dict) -> bool:
    """Whether the process recorded in a lock may still run (always True for another host's, or an unreadable one)."""
    if holder.get("host") != socket.gethostname() or not isinstance(holder.get("pid"), int):
        return True
    try:
        os.kill(holder["pid"], 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _take_lock(folder: Path) -> Path | None:
    """Take ``folder``'s lock (:data:`LOCK`, created atomically); None if this process holds it already.

    Raises :class:`OutputExistsError` while another live process holds it; a dead process's lock is taken over.
    """
    lock = folder / LOCK
    me = {"pid": os.getpid(), "host": socket.gethostname()}
    for old in folder.glob(f"{LOCK}.*"):              # records of commands killed while they took the lock
        pid = old.suffix[1:]
        if pid.isdigit() and not _alive({**me, "pid": int(pid)}):
            with contextlib.suppress(OSError):
                old.unlink()
    tmp = folder / f"{LOCK}.{me['pid']}"              # the lock appears whole: written aside, then linked (atomic,
    tmp.write_text(json.dumps(me))                    # and refused if it exists), so a kill never leaves it empty
    try:
        return _link_lock(folder, lock, tmp, me)
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()


def _link_lock(folder: Path, lock: Path, tmp: Path, me: dict) -> Path | None:
    """:func:`_take_lock`'s attempts: link ``tmp`` (the holder's record) to ``lock``."""
    for _ in range(3):
        try:
            os.link(tmp, lock)
        except FileExistsError:
            holder = _lock_holder(lock)
            if holder == me:
                return None
            if holder is None or (holder and not _alive(holder)):
                with contextlib.suppress(FileNotFoundError):
                    lock.unlink()                         # gone meanwhile, or stale (its process was killed)
                continue
            who = f"pid {holder['pid']}" if holder.get("pid") else "a process starting"
            raise OutputExistsError(f"output folder {str(folder)!r} is in use by another plbar command ({who}); "
                                    "wait until it ends or choose another --out (a stale lock of a dead process "
                                    f"is taken over; of another host, delete {str(lock)!r} by hand)") from None
        _HELD.add(lock)
        return lock
    raise OutputExistsError(f"output folder {str(folder)!r}: its lock {str(lock)!r} keeps changing; choose another "
                            "--out")


def _unlock(lock: Path) -> None:
    """Remove a lock this process holds."""
    if lock in _HELD:
        _HELD.discard(lock)
        with contextlib.suppress(OSError):
            lock.unlink()


@atexit.register
def _unlock_all() -> None:
    for lock in list(_HELD):
        _unlock(lock)


def _refusal(folder: Path, command: str, prev: Owner | None) -> str:
    where = f"output folder {str(folder)!r}"
    if prev is None:
        names = ", ".join(n for n in LEGACY if (folder / n).exists())
        return (f"{where} holds {names} without a plbar owner marker ({MARKER}: written by an older plbar or "
                "by hand); choose another --out or pass --overwrite to replace it")
    if prev.command == command:
        return (f"{where} holds results of another case (written by 'plbar {command}'); choose another --out "
                "or pass --overwrite to replace them")
    return (f"{where} holds the results of 'plbar {prev.command}'; 'plbar {command}' writes elsewhere: choose "
            "another --out, or pass --overwrite to delete those results first")


def check_folder(folder, command: str, fingerprint: str, owned, overwrite: bool = False, joins=()) -> Claim:
    """Apply the ownership rule to ``folder`` without writing anything in it (see the module docstring).

    Parameters
    ----------
    folder : path
        The command's ``--out`` (created if needed, to prove it writable).
    command : str
        The command (``"run"``, ``"sweep-loads"``, ...), recorded in the marker.
    fingerprint : str
        The identity of the case or study (:func:`fingerprint` of its defining data).
    owned : sequence of str
        Glob patterns of what the command writes there (removed when another owner replaces it).
    overwrite : bool
        Replace another owner (its owned files are removed at :meth:`Claim.take`).
    joins : sequence of str
        Commands whose folders (same fingerprint) this command may add its files to.

    Returns
    -------
    Claim
        Call ``take()`` before writing; use it as a context manager to undo it on failure.

    Raises
    ------
    OutputExistsError
        The folder belongs to another command or case, and not ``overwrite``.
    InputError
        The folder cannot be created or written.
    """
    folder = Path(folder)
    created = [p for p in (folder, *folder.parents) if not p.exists()][::-1]
    check_writable(folder)
    claim = Claim(folder, Owner(command, fingerprint, tuple(owned)), None, False, created)
    try:
        claim.lock = _take_lock(folder)
        claim.previous = prev = read_owner(folder)
        if prev is None:
            ok = not any((folder / n).exists() for n in LEGACY)
        else:
            ok = prev.fingerprint == fingerprint and (prev.command == command or prev.command in joins)
        if not ok and not overwrite:
            raise OutputExistsError(_refusal(folder, command, prev))
    except BaseException:
        claim.release()
        raise
    claim.replace = not ok
    return claim


def claim_folder(folder, command: str, fingerprint: str, owned, overwrite: bool = False, joins=()) -> Claim:
    """:func:`check_folder`, then :meth:`Claim.take`: the one line a command needs before it writes."""
    return check_folder(folder, command, fingerprint, owned, overwrite, joins).take()


def check_writable(folder) -> Path:
    """Create ``folder`` if needed and prove that a file can be written there; else a one-line InputError."""
    folder = check_creatable(folder)
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


def check_creatable(folder) -> Path:
    """Refuse (one-line :class:`InputError`) a folder that could not be created or written, without creating it: a
    command validates everything before it makes its folder (the claim makes it, and removes it on failure)."""
    folder = Path(folder)
    for p in (folder, *folder.parents):
        if p.exists():
            if not p.is_dir():
                raise InputError(f"output folder {str(folder)!r} cannot be used: {str(p)!r} is a file; "
                                 "choose another --out")
            if not os.access(p, os.W_OK | os.X_OK):
                raise InputError(f"output folder {str(folder)!r} cannot be written ({str(p)!r} is not writable); "
                                 "choose another --out")
            break
    return folder


def clear_owned(folder, patterns) -> list[Path]:
    """Remove the files and folders matching ``patterns`` (globs) in ``folder``; returns what was removed."""
    folder = Path(folder)
    gone = []
    for p in _matches(folder, dict.fromkeys(patterns)):
        with contextlib.suppress(FileNotFoundError):
            shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()
            gone.append(p)
    return gone


def require(module: str, what: str) -> None:
    """Raise a one-line InputError naming the extra to install if ``module`` is not importable."""
    if importlib.util.find_spec(module) is None:
        extra = EXTRAS.get(module, "all")
        raise InputError(f"{what} needs the optional package {module!r}, which is not installed; "
                         f'install it with: pip install "plbar[{extra}]"')
