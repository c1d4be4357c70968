"""One cache scheme for every kernel: only entry points are cached, each keyed by the stamp of all its sources.

numba keys a cached function by its own file only: an entry point calling an edited function of another file would
load a stale compilation.  Every kernel package's entry points close over its :class:`plbar.util.jit.Kernel`'s
stamp instead (numba's cache key includes a closure's contents), so an edit anywhere compiles afresh.
"""

import plbar.continuum.kernel.accounts as ca
import plbar.continuum.kernel.fields as cf
import plbar.motion.kernel.loop as ml
import plbar.periodic.kernel as pk
from plbar.continuum.kernel import jit as cjit
from plbar.continuum.kernel import march
from plbar.motion.kernel import jit as mjit
from plbar.periodic.kernel import stamp as pjit
from plbar.util import jit as policy


def test_a_stamp_changes_with_any_source_and_the_salt(tmp_path):
    a, b = tmp_path / "a.py", tmp_path / "b.py"
    a.write_text("x = 1\n")
    b.write_text("y = 2\n")
    k = policy.kernel([a, b])
    assert policy.Path(policy.__file__).resolve() in k.sources          # the policy itself is a source
    assert policy.kernel([b, a]).key == k.key                           # the order of the sources does not count
    assert policy.kernel([a, b], salt="1").key != k.key
    b.write_text("y = 3\n")
    assert policy.kernel([a, b]).key != k.key


def _closure(entry) -> tuple:
    return tuple(c.cell_contents for c in entry.py_func.__closure__ or ())


def test_every_entry_point_is_cached_and_closes_over_its_package_stamp():
    entries = {mjit.STAMP: [ml.advance],
               pjit.STAMP: [pk.chain, pk.step, pk.polish, pk.monodromy, pk.energy],
               cjit.STAMP: [march, cf.w_out_into, cf.invariants_into, ca.space_into, ca.work_into]}
    for key, funcs in entries.items():
        for f in funcs:
            assert f._cache._cache_path, f
            assert _closure(f) == (key,), f


def test_the_helpers_are_not_cached_on_their_own():
    import plbar.continuum.kernel.end as ce
    import plbar.motion.kernel.closed as mc

    for f in (ce.free, ce.brentq, mc.mode_flow, pk.walk.copy):
        assert type(f._cache).__name__ == "NullCache", f
