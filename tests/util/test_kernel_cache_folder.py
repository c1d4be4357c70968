"""Every kernel caches in one per-user folder, never inside the installed package.

numba caches beside a module's source by default; for an installed plbar that is inside ``site-packages``, where
pip does not own the files: the README's second command (``pip install -e``) left them behind as a ``plbar/``
folder that shadowed the editable install (``cannot import name '__version__' from 'plbar'``).
"""

import json
import subprocess
import sys
from pathlib import Path

import plbar
from plbar.util.jit import cache_root

PACKAGE = Path(plbar.__file__).resolve().parent

# import every kernel package (numba decorates: each cached function's folder is chosen, nothing compiles) and list
# the folder of every cached function, and every cache file under the package
_PROBE = r"""
import json, sys
from pathlib import Path
import plbar
import plbar.motion.kernel, plbar.periodic.kernel, plbar.continuum.kernel
from numba.core.registry import CPUDispatcher
paths = set()
for name, mod in list(sys.modules.items()):
    if name.startswith("plbar."):
        for obj in vars(mod).values():
            cache = getattr(obj, "_cache", None) if isinstance(obj, CPUDispatcher) else None
            if getattr(cache, "_cache_path", None):
                paths.add(cache._cache_path)
package = Path(plbar.__file__).resolve().parent
inside = [str(p) for p in package.rglob("*") if p.suffix in (".nbi", ".nbc", ".ok", ".stamp")]
print(json.dumps({"paths": sorted(paths), "inside": inside}))
"""


def test_cache_root_follows_the_environment(tmp_path):
    assert cache_root({"PLBAR_CACHE_DIR": str(tmp_path / "a"), "NUMBA_CACHE_DIR": "/x"}) == tmp_path / "a"
    assert cache_root({"NUMBA_CACHE_DIR": str(tmp_path / "b")}) == tmp_path / "b"
    assert cache_root({"XDG_CACHE_HOME": str(tmp_path)}) == tmp_path / "plbar" / "numba"
    assert cache_root({}) == Path("~").expanduser() / ".cache" / "plbar" / "numba"


def test_every_kernel_caches_in_the_per_user_folder_and_nothing_in_the_package(tmp_path):
    env = {k: v for k, v in __import__("os").environ.items() if not k.startswith(("NUMBA_", "PLBAR_"))}
    env["PLBAR_CACHE_DIR"] = str(tmp_path / "cache")
    out = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, check=True)
    got = json.loads(out.stdout.strip().splitlines()[-1])
    assert len(got["paths"]) >= 3                                   # motion, hybrid and continuum entries
    for p in got["paths"]:
        assert Path(p).resolve().is_relative_to((tmp_path / "cache").resolve()), p
        assert not Path(p).resolve().is_relative_to(PACKAGE), p
    assert got["inside"] == []                                      # the continuum's stamp was written outside
