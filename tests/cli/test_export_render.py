"""``plbar export`` and ``plbar render``: the ParaView data and images of a run folder, the options they refuse before
making anything, the optional package they need.

From the newcomer reports (the first hour and issue 22). Every test here failed on the code before the fix it covers.
"""

import pytest

from plbar.cli import main

from _helpers import FAST, PAPER, ROOT, _refused, _run


def test_export_clears_the_other_format(tmp_path, capsys):
    pytest.importorskip("pyvista")
    out = tmp_path / "r"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "40", "40", "--out", out, "-q", "--no-plot"])[0] == 0
    (out / "vtk").mkdir()
    for name in ("response.xdmf", "response.h5", "response_0099.vtu"):
        (out / "vtk" / name).write_text("stale")
    assert _run(capsys, ["export", "--from", out, "--steps", "8", "-q"])[0] == 0
    names = sorted(p.name for p in (out / "vtk").iterdir())
    assert "response.pvd" in names and "response.xdmf" not in names and "response.h5" not in names
    assert "response_0099.vtu" not in names and len([n for n in names if n.endswith(".vtu")]) == 8


@pytest.mark.parametrize("cmd, opts, word", [
    ("export", ["--branch", "99"], "branch = 99"), ("export", ["--index", "999"], "index = 999"),
    ("export", ["--steps", "2"], "--steps 2"), ("render", ["--field", "bogus"], "--field bogus"),
    ("render", ["--snapshots", "0"], "--snapshots 0"), ("render", ["--branch", "99"], "branch = 99")])
def test_bad_export_and_render_options_create_nothing(tmp_path, capsys, cmd, opts, word):
    pytest.importorskip("pyvista")
    R = tmp_path / "R"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--out", R, *FAST])[0] == 0
    _refused(capsys, [cmd, "--from", R, "--out", tmp_path / "d", *opts], word)
    assert not (tmp_path / "d").exists()


def test_missing_pyvista_names_the_extra(tmp_path, capsys, monkeypatch):
    out = tmp_path / "r"
    assert _run(capsys, ["run", *PAPER, "-N", "4", "--grid", "40", "40", "--out", out, "-q", "--no-plot"])[0] == 0
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pyvista" else real(name, *a))
    code, _, err = _run(capsys, ["export", "--from", out])
    assert code == 2 and 'pip install "plbar[vtk]"' in err and not (out / "vtk").exists()
    code, _, err = _run(capsys, ["render", "--from", out])
    assert code == 2 and 'pip install "plbar[vtk]"' in err and not (out / "render").exists()


def test_export_index_minus_one_is_documented(capsys):
    assert main(["export", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "-1" in text and "last" in text
    assert "--index -1" in (ROOT / "README.md").read_text()
