"""The continuum kernels' on-disk cache is emptied when their sources change (numba alone would load a stale one)."""

from plbar.continuum.kernel.jit import STAMP, clear_stale


def test_a_cache_from_other_sources_is_emptied(tmp_path):
    (tmp_path / "march.march-199.py311.nbi").write_text("x")
    (tmp_path / "march.march-199.py311.1.nbc").write_text("x")
    (tmp_path / "plbar-continuum-0000000000000000.stamp").write_text("")
    assert clear_stale(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"plbar-continuum-{STAMP:x}.stamp"]
    (tmp_path / "end.free-45.py311.nbi").write_text("x")          # compiled from these sources: kept
    assert not clear_stale(tmp_path)
    assert (tmp_path / "end.free-45.py311.nbi").exists()
