"""The one numba policy of every compiled kernel: its options, where its on-disk cache lives, and its stamp.

Every kernel package (:mod:`plbar.motion.kernel`, :mod:`plbar.periodic.kernel`, :mod:`plbar.continuum.kernel`)
compiles through this module and nothing else, in one way: a :class:`Kernel` made by :func:`kernel` from the
package's sources.  It is imported only by them, so that importing plbar imports no numba (:mod:`plbar.util` does
not re-export it).

* **Options** (:data:`OPTIONS`): no GIL (``nogil=True``: :func:`plbar.util.threads.map_chunks` runs trajectories
  on every core) and numpy's error model (a division by zero is ``inf``/``nan`` as in numpy: the closed forms test
  for it).
* **Where the cache lives** (:func:`cache_root`): one folder per user, never inside the installed package.  numba
  caches beside a module's source (``__pycache__``) by default; for an installed plbar that is inside
  ``site-packages``, in files pip does not own: uninstalling (as ``pip install -e`` does before an editable
  install) leaves a ``plbar/`` folder of cache files behind, a namespace package that shadows the new install
  (``ImportError: cannot import name '__version__' from 'plbar' (unknown location)``).  The folder is
  ``$PLBAR_CACHE_DIR`` if set, else numba's own ``$NUMBA_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/plbar/numba``
  (``~/.cache/plbar/numba``); numba names each module's subfolder after the module's folder path, so two installs
  never share an entry.
* **What is cached, and the stamp** (:class:`Kernel`): only the entry points (the functions Python calls) are
  cached on disk; the helpers (:func:`jit`) are compiled into them, and get no CPython or C wrapper (a quarter of
  a kernel's first compile, measured: the simulator's 16.6 s -> 12.2 s, the chain's 6.2 s -> 4.9 s); Python
  calls a helper through :func:`python_twin` (the tests do).  numba keys a cached function by its own file
  only, so a change in a function it calls from another file would not be seen (a stale kernel after an edit or
  an upgrade).  So an entry point is written as a factory of one argument, the :func:`stamp` of every source it is
  built from (:meth:`Kernel.cached`): the function it returns closes over the stamp, and numba's cache key
  includes the closure's contents: any change of any source compiles afresh, and no cache file is ever deleted.
* **Which specialisations are compiled** (:meth:`Kernel.is_compiled`, :meth:`Kernel.mark_compiled`): a marker
  file per entry point, stamp, numba version and kind, in the entry point's cache folder, so that a caller can
  say beforehand that a first call compiles.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import numba
from numba.core.caching import _CacheLocator

__all__ = ["OPTIONS", "HELPER", "Kernel", "cache_root", "cache_folder", "stamp", "jit", "kernel", "cached",
           "is_compiled", "mark_compiled", "python_twin"]

OPTIONS = {"nogil": True, "error_model": "numpy"}   #: every kernel function's numba options
#: a helper's options besides: called from compiled code only, so numba builds no wrapper for Python or C callers
HELPER = {"no_cpython_wrapper": True, "no_cfunc_wrapper": True}


def cache_root(environ: dict | None = None) -> Path:
    """The per-user folder of every kernel's on-disk cache (see the module's docstring for the order).

    Parameters
    ----------
    environ : dict, optional
        The environment to read (``os.environ``).
    """
    env = os.environ if environ is None else environ
    for var in ("PLBAR_CACHE_DIR", "NUMBA_CACHE_DIR"):
        if env.get(var):
            return Path(env[var]).expanduser()
    base = env.get("XDG_CACHE_HOME") or str(Path("~").expanduser() / ".cache")
    return Path(base) / "plbar" / "numba"


def _use_cache_root() -> None:
    """Point numba's cache at :func:`cache_root` (a writable folder: else one under the temporary folder)."""
    root = cache_root()
    try:
        root.mkdir(parents=True, exist_ok=True)
        ok = os.access(root, os.W_OK)
    except OSError:
        ok = False
    if not ok:
        root = Path(tempfile.gettempdir()) / f"plbar-{os.getuid() if hasattr(os, 'getuid') else 'user'}" / "numba"
        root.mkdir(parents=True, exist_ok=True)
    # numba reads NUMBA_CACHE_DIR from the environment on every compile when any NUMBA_ variable changed, and its
    # config otherwise: both say the same folder (workers started from here inherit it)
    os.environ["NUMBA_CACHE_DIR"] = str(root)
    numba.config.CACHE_DIR = str(root)


_use_cache_root()


def cache_folder(source: Path) -> Path:
    """The folder in which numba caches the functions of the module file ``source``."""
    return Path(numba.config.CACHE_DIR) / _CacheLocator.get_suitable_cache_subpath(str(Path(source).resolve()))


def stamp(sources: Iterable[Path], salt: str = "") -> int:
    """60 bits of the hash of ``salt``, numba's version and the contents of every file in ``sources``."""
    h = hashlib.sha256((salt + numba.__version__).encode())
    for path in sources:
        h.update(Path(path).name.encode() + Path(path).read_bytes())
    return int(h.hexdigest()[:15], 16)


def jit(*, inline: bool = False, nrt: bool = True):
    """The decorator of a kernel function (not cached on its own: compiled into the entry points that call it,
    :meth:`Kernel.cached`).

    Parameters
    ----------
    inline : bool
        Inline it where it is called (constants propagate; no call overhead on arrays).
    nrt : bool
        numba's reference counting; without it, every array view and every array taken from a tuple costs no
        atomic increment and decrement (measured at 42 % of the motion kernel's time), and the function must
        allocate nothing.

    The helper has no wrapper for Python callers (:data:`HELPER`): calling it from Python crashes the process;
    :func:`python_twin` is the way.
    """
    return numba.njit(inline="always" if inline else "never", _nrt=nrt, **HELPER, **OPTIONS)


def python_twin(helper: Callable) -> Callable:
    """The same source as a kernel helper (:func:`jit`), compiled apart with a wrapper: what Python calls to test
    a helper on its own (the helper itself has none: :data:`HELPER`).  Anything else is returned as it is."""
    if not getattr(helper, "targetoptions", {}).get("no_cpython_wrapper"):
        return helper
    twin = _TWINS.get(helper)
    if twin is None:
        opts = {k: v for k, v in helper.targetoptions.items() if k not in HELPER and k not in ("inline", "nopython")}
        twin = _TWINS[helper] = numba.njit(**opts)(helper.py_func)
    return twin


_TWINS: dict = {}


def cached(factory: Callable[[int], Callable], key: int) -> Callable:
    """Compile ``factory(key)`` -- a function whose body uses its argument, so that it is in its closure -- with an
    on-disk cache keyed by ``key`` (a :func:`stamp`) as well as by its own file."""
    return numba.njit(cache=True, **OPTIONS)(factory(key))


def _marker(entry, key: int, kind: str) -> Path | None:
    """The file that says ``entry`` is compiled for ``kind`` in its on-disk cache (None where numba has none)."""
    folder = getattr(getattr(entry, "_cache", None), "_cache_path", None)
    return Path(folder) / f"plbar-{key:x}-numba{numba.__version__}-{kind}.ok" if folder else None


def is_compiled(entry, kind: str, key: int) -> bool:
    """Whether ``entry`` has been compiled for ``kind`` (one specialisation: a name the caller chooses) from the
    sources stamped ``key`` with this numba, so that a call loads it from the cache in a fraction of a second.
    Where it cannot tell, True."""
    m = _marker(entry, key, kind)
    return m is None or m.exists()


def mark_compiled(entry, kind: str, key: int) -> None:
    """Record that ``entry`` is compiled for ``kind`` (:func:`is_compiled`); a read-only cache is left alone."""
    m = _marker(entry, key, kind)
    if m is not None:
        with contextlib.suppress(OSError):
            m.parent.mkdir(parents=True, exist_ok=True)
            m.touch()


@dataclass(frozen=True)
class Kernel:
    """How one kernel package compiles: the sources its entry points are built from and their :func:`stamp`.

    Attributes
    ----------
    sources : tuple of Path
        Every file the package's compiled code is built from (its modules, the constants it imports, this policy).
    key : int
        The :func:`stamp` of ``sources`` (and of the salt :func:`kernel` was given).
    """

    sources: tuple
    key: int

    def cached(self, factory: Callable[[int], Callable]) -> Callable:
        """The entry point ``factory(key)``, cached on disk keyed by :attr:`key` (:func:`cached`)."""
        return cached(factory, self.key)

    def is_compiled(self, entry, kind: str, stamp: int | None = None) -> bool:
        """:func:`is_compiled` of ``entry`` for ``kind``, from these sources (or those stamped ``stamp``)."""
        return is_compiled(entry, kind, self.key if stamp is None else stamp)

    def mark_compiled(self, entry, kind: str, stamp: int | None = None) -> None:
        """:func:`mark_compiled` of ``entry`` for ``kind``, from these sources (or those stamped ``stamp``)."""
        mark_compiled(entry, kind, self.key if stamp is None else stamp)


def kernel(sources: Iterable[Path], salt: str = "") -> Kernel:
    """The :class:`Kernel` of a package built from ``sources`` (this policy's own file is added), its stamp salted
    with ``salt`` (the stamp of another kernel whose functions it compiles in)."""
    files = tuple(sorted({Path(p).resolve() for p in sources} | {Path(__file__).resolve()}))
    return Kernel(files, stamp(files, salt))
