"""Every bad input gets a clear, typed error; no nan escapes; results are never half-written.

Each API case asserts the error type (a ``PlbarError``, hence a
``ValueError``), that the message names the offending value as a plain
Python number (never ``np.float64(...)``) and the allowed range.  Each CLI
case asserts exit code 2 and exactly one line on stderr.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import warnings
from pathlib import Path

import meshio
import numpy as np
import pytest

import plbar
from plbar.util import files as pio
from plbar.app import loads_case
from plbar.cli import main
from plbar.errors import (CaseFileError, CoarseGridWarning, InputError, NonFiniteError, OutputExistsError,
                          PlbarError)
from plbar.io import read_nodes, write_nodes

PAPER = ["--signatures", "paper"]      # the paper's class only: these runs are not about the other signatures

B5 = plbar.chain(5)


def _prob(load, bar=None):
    return plbar.problem(bar or plbar.uniform_bar(4), load)


# (id, callable, error type, substrings the message must contain: the value and the allowed range)
API = [
    ("length-zero", lambda: plbar.uniform_bar(4, length=0.0), InputError, ["length = 0.0", "> 0"]),
    ("length-negative", lambda: plbar.uniform_bar(4, length=-1), InputError, ["length = -1.0", "> 0"]),
    ("length-nan", lambda: plbar.uniform_bar(4, length=float("nan")), InputError, ["length = nan", "finite"]),
    ("length-inf", lambda: plbar.uniform_bar(4, length=np.inf), InputError, ["length = inf", "finite"]),
    ("length-string", lambda: plbar.uniform_bar(4, length="1"), InputError, ["length = '1'", "not a number"]),
    ("length-None", lambda: plbar.uniform_bar(4, length=None), InputError, ["length = None", "not a number"]),
    ("EA-np-float64", lambda: plbar.uniform_bar(4, EA=np.float64(-2.0)), InputError, ["EA = -2.0", "> 0"]),
    ("EA-bool", lambda: plbar.uniform_bar(4, EA=True), InputError, ["EA = True", "> 0"]),
    ("EA-per-element-zero", lambda: plbar.Bar(plbar.uniform_nodes(3), EA=[1.0, 0.0, 2.0]), InputError,
     ["EA[1] = 0.0", "> 0"]),
    ("EA-per-element-shape", lambda: plbar.Bar(plbar.uniform_nodes(3), EA=[1.0, 2.0]), InputError,
     ["3 values", "shape (2,)"]),
    ("EA-contrast", lambda: plbar.Bar(plbar.uniform_nodes(3), EA=[1.0, 1e-9, 1.0]), InputError,
     ["from 1e-09 to 1.0", "at most 10000"]),
    ("rhoA-string", lambda: plbar.Bar(plbar.uniform_nodes(3), rhoA="abc"), InputError, ["rhoA = 'abc'", "> 0"]),
    ("chain-mass-zero", lambda: plbar.chain(5, m=0.0), InputError, ["m = 0.0", "> 0"]),
    ("point-mass-negative", lambda: plbar.Bar(plbar.uniform_nodes(3), point_masses=((1.0, -1.0),)), InputError,
     ["point mass = -1.0", "> 0"]),
    ("point-mass-off-vertex", lambda: plbar.Bar(plbar.uniform_nodes(3), point_masses=((0.5, 1.0),)), InputError,
     ["x = 0.5", "free vertex", "(0, 1]"]),
    ("one-element", lambda: plbar.uniform_bar(1), InputError, ["number of elements = 1", ">= 2"]),
    ("zero-elements", lambda: plbar.Bar([0.0]), InputError, ["at least 2 elements", "shape (1,)"]),
    ("one-element-nodes", lambda: plbar.Bar([0.0, 1.0]), InputError, ["at least 2 elements", "shape (2,)"]),
    ("elements-float", lambda: plbar.uniform_bar(2.0), InputError, ["number of elements = 2.0", "integer >= 2"]),
    ("chain-N-bool", lambda: plbar.chain(True), InputError, ["chain size N = True", "integer >= 2"]),
    ("nodes-unsorted", lambda: plbar.Bar([0.0, 2.0, 1.0, 3.0]), InputError, ["unsorted", "x = 2.0, 1.0",
                                                                           "strictly increasing"]),
    ("nodes-duplicate", lambda: plbar.Bar([0.0, 1.0, 1.0, 3.0]), InputError, ["duplicate", "x = 1.0, 1.0"]),
    ("nodes-not-at-clamp", lambda: plbar.Bar([0.5, 1.0, 2.0]), InputError, ["x = 0.5", "x = 0"]),
    ("nodes-nan", lambda: plbar.Bar([0.0, 1.0, np.nan]), InputError, ["x = nan", "finite"]),
    ("nodes-string", lambda: plbar.Bar("0 1 2"), InputError, ["nodes = '0 1 2'", "starting at 0"]),
    ("element-too-short", lambda: plbar.Bar([0.0, 1e-12, 0.5, 1.0]), InputError, ["1e-12", "at least 1e-05 L"]),
    ("grading-extreme", lambda: plbar.graded_nodes(5, ratio=1e6), InputError, ["ratio = 1000000.0",
                                                                                "[0.001, 1000]"]),
    ("chain-k-overflowing", lambda: plbar.chain(3, k=1e300), InputError, ["k = 1e+300", "between 1e-24 and 1e+24"]),
    ("EA-underflowing", lambda: plbar.uniform_bar(3, EA=1e-300), InputError, ["EA = 1e-300", "between 1e-24"]),
    ("element-P3", lambda: plbar.Bar(plbar.uniform_nodes(3), element="P3"), InputError, ["element = 'P3'",
                                                                                        "P1, P2"]),
    ("load-at-clamp", lambda: plbar.point(0.0), InputError, ["s = 0.0", "(0, L]"]),
    ("load-negative", lambda: plbar.point(-0.5), InputError, ["s = -0.5", "(0, L]"]),
    ("load-beyond-L", lambda: _prob(plbar.point(1.5)), InputError, ["s = 1.5", "(0, 1]"]),
    ("load-next-to-clamp", lambda: _prob(plbar.point(1e-13)), InputError, ["s = 1e-13", "clamped end"]),
    ("load-nan-position", lambda: plbar.point(float("nan")), InputError, ["s = nan", "(0, L]"]),
    ("load-string-position", lambda: plbar.point("0.5"), InputError, ["s = '0.5'", "(0, L]"]),
    ("load-all-zero", lambda: plbar.Case(model="fe", load_points=((0.5, 0.0),)), InputError,
     ["amplitude is 0.0", "non-zero"]),
    ("load-cancels", lambda: _prob(plbar.node(1) + plbar.node(1, -1.0)), InputError, ["cancel", "non-zero"]),
    ("load-amplitude-inf", lambda: plbar.point(0.5, np.inf), InputError, ["amplitude = inf", "1e+24"]),
    ("load-amplitude-huge", lambda: plbar.point(0.5, 1e300), InputError, ["amplitude = 1e+300", "1e+24"]),
    ("load-amplitude-bool", lambda: plbar.point(0.5, True), InputError, ["amplitude = True", "not a number"]),
    ("load-node-zero", lambda: plbar.node(0), InputError, ["load node = 0", ">= 1"]),
    ("load-node-out-of-range", lambda: plbar.problem(B5, plbar.node(6)), InputError, ["load node = 6", "1..5"]),
    ("load-node-float", lambda: plbar.node(1.5), InputError, ["load node = 1.5", "integer"]),
    ("load-malformed", lambda: plbar.Load(points=(0.5,)), InputError, ["entry = 0.5", "(s, amplitude)"]),
    ("load-empty", lambda: plbar.Load(), InputError, ["empty", "at least one"]),
    ("domain-negative", lambda: plbar.Domain((-1.0, 2.0), (0.0, 3.0)), InputError, ["T1 = (-1.0, 2.0)",
                                                                                      "0 <= low < high"]),
    ("domain-T-zero", lambda: plbar.Domain((0.0, 2.0), (0.0, 0.0)), InputError, ["T2 = (0.0, 0.0)",
                                                                                   "0 <= low < high"]),
    ("domain-reversed", lambda: plbar.Domain((3.0, 1.0), (0.0, 3.0)), InputError, ["T1 = (3.0, 1.0)", "reversed",
                                                                                     "0 <= low < high"]),
    ("domain-nan", lambda: plbar.Domain((0.0, np.nan), (0.0, 3.0)), InputError, ["T1 = (0.0, nan)", "finite"]),
    ("domain-np-float64", lambda: plbar.Domain((np.float64(3), np.float64(2)), (0, 3)), InputError,
     ["T1 = (3.0, 2.0)"]),
    ("domain-bool", lambda: plbar.Domain((False, True), (0.0, 3.0)), InputError, ["T1 = False", "not a number"]),
    ("domain-string", lambda: plbar.Domain("ab", (0.0, 3.0)), InputError, ["T1 = 'ab'", "pair (low, high)"]),
    ("domain-low-subnormal", lambda: plbar.Domain((5e-309, 2.0), (0.0, 3.0)), InputError,
     ["T1 = (5e-309, 2.0)", "low must be 0"]),
    ("case-grid-too-small", lambda: plbar.Case(grid=(2, 50)), InputError, ["grid = (2, 50)", ">= 3"]),
    ("case-grid-float", lambda: plbar.Case(grid=(20.5, 30)), InputError, ["20.5", "integers >= 3"]),
    ("case-grid-string", lambda: plbar.Case(grid="ab"), InputError, ["grid = 'ab'", "(N1, N2) >= 3"]),
    ("case-n-string", lambda: plbar.Case(n="5"), InputError, ["N = '5'", "integer >= 2"]),
    ("case-T1-reversed", lambda: plbar.Case(T1=(3.0, 1.0)), InputError, ["T1 = (3.0, 1.0)", "0 <= low < high"]),
    ("case-chain-P2", lambda: plbar.Case(element="P2"), InputError, ["P1 lumped", "model = 'fe'"]),
    ("case-fe-grading", lambda: plbar.Case(model="fe", grading=-2.0), InputError, ["grading = -2.0", "> 0"]),
    ("case-load-malformed", lambda: plbar.Case(load_points=(1.0,)), InputError, ["entry = 1.0",
                                                                                   "(s, amplitude)"]),
    ("solve-not-a-case", lambda: plbar.solve("case.toml"), InputError, ["case = 'case.toml'", "plbar.Case"]),
    ("problem-zero-q", lambda: plbar.problem(B5, q=np.zeros(5)), InputError, ["non-zero", "length 5"]),
]


@pytest.mark.parametrize("make, etype, expect", [a[1:] for a in API], ids=[a[0] for a in API])
def test_api_bad_input(make, etype, expect):
    with pytest.raises(etype) as exc:
        make()
    msg = str(exc.value)
    assert isinstance(exc.value, PlbarError) and isinstance(exc.value, ValueError)
    assert "\n" not in msg and "np.float64" not in msg and "np.int" not in msg, msg
    for e in expect:
        assert e in msg, f"{e!r} not in {msg!r}"


def test_api_cases_are_many_and_distinct():
    assert len(API) >= 25 and len({a[0] for a in API}) == len(API)


# --- mesh files ----------------------------------------------------------------------------------

def _mesh(path, x, cells, y=None):
    x = np.asarray(x, float)
    pts = np.c_[x, np.zeros_like(x) if y is None else y, np.zeros_like(x)]
    with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
        warnings.simplefilter("ignore")
        meshio.write(str(path), meshio.Mesh(pts, [(t, np.asarray(c)) for t, c in cells]), file_format="gmsh22",
                     binary=False)
    return path


X5 = [0.0, 0.25, 0.5, 0.75, 1.0]
MESHES = [
    ("no-line-cells", X5, [("vertex", [[0], [1], [2], [3], [4]])], None, ["no line cells", "found: vertex"]),
    ("triangles-only", X5, [("triangle", [[0, 1, 2], [2, 3, 4]])], np.array(X5) ** 2, ["no line cells",
                                                                                          "triangle"]),
    ("branched", X5, [("line", [[0, 1], [1, 2], [1, 3], [3, 4]])], None, ["branched", "x = 0.25", "3 lines"]),
    ("disconnected", X5, [("line", [[0, 1], [1, 2], [3, 4]])], None, ["disconnected", "one chain"]),
    ("closed-loop", X5, [("line", [[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]])], None, ["loop", "open chain"]),
    ("duplicate-vertex", [0.0, 0.5, 0.5, 1.0], [("line", [[0, 1], [1, 2], [2, 3]])], None, ["x = 0.5",
                                                                                         "distinct"]),
    ("not-at-clamp", [0.1, 0.5, 0.7, 1.0], [("line", [[0, 1], [1, 2], [2, 3]])], None, ["x = 0.1", "x = 0"]),
    ("skipping-line", [0.0, 0.5, 0.7, 1.0], [("line", [[0, 2], [2, 1], [1, 3]])], None, ["x = 0 to x = 0.7",
                                                                                       "neighbouring"]),
    ("self-loop", [0.0, 0.5, 1.0], [("line", [[0, 1], [1, 1], [1, 2]])], None, ["to itself", "x = 0.5"]),
    ("off-axis", X5, [("line", [[0, 1], [1, 2], [2, 3], [3, 4]])], np.array(X5) ** 2, ["[1.0, 1.0, 0.0]",
                                                                                        "y and z must be 0"]),
]


@pytest.mark.parametrize("x, cells, y, expect", [m[1:] for m in MESHES], ids=[m[0] for m in MESHES])
def test_mesh_file_bad(tmp_path, x, cells, y, expect):
    f = _mesh(tmp_path / "bad.msh", x, cells, y)
    with pytest.raises(InputError) as exc:
        read_nodes(f)
    msg = str(exc.value)
    assert "bad.msh" in msg and "\n" not in msg
    for e in expect:
        assert e in msg, f"{e!r} not in {msg!r}"
    # the same mistake through a case (API) and a case file
    with pytest.raises(InputError, match="bad.msh"):
        plbar.Case(model="fe", mesh_file=str(f)).problem()
    with pytest.raises(CaseFileError, match="c.toml: .*bad.msh"):
        loads_case(f'[bar]\nmodel = "fe"\nmesh_file = "{f}"\n[[load]]\nat = 0.5\n', "c.toml")


def test_mesh_file_unreadable_and_single_element(tmp_path):
    g = tmp_path / "garbage.msh"
    g.write_text("hello\n")
    with pytest.raises(InputError, match="garbage.msh' cannot be read by meshio"):
        read_nodes(g)                       # meshio calls sys.exit(1) here: caught, not an exit
    with pytest.raises(InputError, match="does not exist"):
        read_nodes(tmp_path / "nope.msh")
    one = tmp_path / "one.msh"
    write_nodes(one, [0.0, 1.0])
    with pytest.raises(InputError, match=r"one.msh.*at least 2 elements"):
        plbar.Case(model="fe", mesh_file=str(one)).problem()


# --- case files ----------------------------------------------------------------------------------

GOOD = '[bar]\nmodel = "chain"\nn = 4\n[[load]]\nnode = 1\n[search]\ngrid = [30, 30]\n'


@pytest.mark.parametrize("old, new, expect", [
    ("grid = [30, 30]", "grid = [30, 30]\nT1 = [3.0, 1.0]", ["T1 = (3.0, 1.0)", "0 <= low < high"]),
    ("grid = [30, 30]", "grid = [30, 30]\nT2 = [-1.0, 1.0]", ["T2 = (-1.0, 1.0)", "0 <= low < high"]),
    ("node = 1", "at = 0.0", ["s = 0.0", "(0, L]"]),
    ("node = 1", "at = 4.5", ["s = 4.5", "(0, 4]"]),
    ("node = 1", "node = 1\namplitude = 0.0", ["amplitude is 0.0", "non-zero"]),
    ("node = 1", "at = nan", ["at = nan", "finite"]),
    ("n = 4", "n = 4\nm = -1.0", ["m = -1.0", "> 0"]),
    ("grid = [30, 30]", "grid = [30, 1]", ["grid = (30, 1)", ">= 3"]),
    ("grid = [30, 30]", "grid = [30, 30]\n[output]\nbranch = -1", ["branch = -1", ">= 0"]),
])
def test_case_file_bad(old, new, expect):
    with pytest.raises(CaseFileError) as exc:
        loads_case(GOOD.replace(old, new), "c.toml")
    msg = str(exc.value)
    assert msg.startswith("c.toml: ") and "\n" not in msg
    for e in expect:
        assert e in msg, f"{e!r} not in {msg!r}"


# --- command line: exit code 2 and one line on stderr -------------------------------------------

def _cli(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, err


CLI = [
    ("grid-too-small", ["--grid", "2", "2"], ["grid = (2, 2)", ">= 3"]),
    ("grid-not-int", ["--grid", "x", "10"], ["invalid int value: 'x'"]),
    ("elements-one", ["--elements", "1"], ["N = 1", ">= 2"]),
    ("fe-elements-one", ["--model", "fe", "--elements", "1"], ["n = 1", ">= 2"]),
    ("load-at-clamp", ["--load-at", "0"], ["s = 0.0", "(0, L]"]),
    ("load-beyond", ["--load-at", "99"], ["s = 99.0", "(0, 5]"]),
    ("load-nan", ["--load-at", "nan"], ["s = nan", "(0, L]"]),
    ("load-node-zero", ["--load-node", "0"], ["load node = 0", ">= 1"]),
    ("load-node-out-of-range", ["--load-node", "9"], ["load node = 9", "1..5"]),
    ("T1-reversed", ["--T1", "3", "1"], ["T1 = (3.0, 1.0)", "0 <= low < high"]),
    ("T2-negative", ["--T2", "-1", "2"], ["T2 = (-1.0, 2.0)", "0 <= low < high"]),
    ("T1-inf", ["--T1", "0", "inf"], ["T1 = (0.0, inf)", "finite"]),
    ("grading-negative", ["--model", "fe", "--grading", "-1"], ["grading = -1.0", "> 0"]),
    ("chain-with-P2", ["--element", "P2"], ["P1 lumped"]),
    ("unknown-option", ["--bogus"], ["unrecognized arguments: --bogus"]),
    ("bad-choice", ["--mass", "heavy"], ["invalid choice: 'heavy'"]),
    ("missing-mesh-file", ["--model", "fe", "--mesh-file", "nope.msh"], ["'nope.msh' does not exist"]),
    ("missing-case-file", ["nope.toml"], ["nope.toml: cannot read"]),
]


@pytest.mark.parametrize("args, expect", [c[1:] for c in CLI], ids=[c[0] for c in CLI])
def test_cli_bad_input(capsys, tmp_path, args, expect):
    code, err = _cli(capsys, ["run", "--out", str(tmp_path / "o"), "--no-plot", "-q"] + args)
    assert code == 2
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1 and lines[0].startswith("plbar"), err
    for e in expect:
        assert e in err, f"{e!r} not in {err!r}"
    assert not (tmp_path / "o").exists()              # nothing written


def test_cli_bad_mesh_and_case_file(capsys, tmp_path):
    f = _mesh(tmp_path / "br.msh", X5, [("line", [[0, 1], [1, 2], [1, 3], [3, 4]])])
    code, err = _cli(capsys, ["run", *PAPER, "--out", str(tmp_path / "o"), "--model", "fe", "--mesh-file", str(f)])
    assert code == 2 and err.count("\n") == 1 and "branched" in err
    c = tmp_path / "c.toml"
    c.write_text(GOOD.replace("n = 4", "n = 4\nlenght = 2.0"))
    code, err = _cli(capsys, ["run", str(c), "--out", str(tmp_path / "o")])
    assert code == 2 and err.count("\n") == 1 and 'unknown key "lenght"' in err


def test_cli_other_commands_bad_input(capsys, tmp_path):
    code, err = _cli(capsys, ["nope"])
    assert code == 2 and err.count("\n") == 1 and "invalid choice: 'nope'" in err
    code, err = _cli(capsys, ["render", "--out", str(tmp_path / "missing")])
    assert code == 2 and err.count("\n") == 1 and "summary.json" in err


def test_cli_out_is_a_file(capsys, tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    code, err = _cli(capsys, ["run", *PAPER, "--out", str(f / "sub"), "--grid", "24", "24", "--no-plot", "-q"])
    assert code == 2 and err.count("\n") == 1 and "is a file" in err


# --- reruns into the same folder ------------------------------------------------------------------

def test_rerun_same_case_other_case_and_overwrite(capsys, tmp_path):
    out = tmp_path / "o"
    base = ["run", *PAPER, "--out", str(out), "--no-plot", "-q", "--method", "grid"]
    assert main(base + ["--grid", "24", "24"]) == 0
    first = (out / "paths.csv").read_text()
    assert main(base + ["--grid", "24", "24"]) == 0                 # same case: replaced
    assert (out / "paths.csv").read_text() == first
    capsys.readouterr()
    code, err = _cli(capsys, base + ["--grid", "25", "24"])        # another case: refused before solving
    assert code == 2 and err.count("\n") == 1
    assert "holds results of another case" in err and "--overwrite" in err
    assert (out / "paths.csv").read_text() == first                # kept
    assert main(base + ["--grid", "25", "24", "--overwrite"]) == 0
    assert json.loads((out / "summary.json").read_text())["case"]["grid"] == [25, 24]


def test_write_results_refuses_other_case_and_unreadable_summary(tmp_path):
    res = plbar.solve(plbar.Case(signatures="paper", n=3, grid=(24, 24), method="grid"))
    other = plbar.solve(plbar.Case(signatures="paper", n=3, grid=(24, 24), method="grid", load_nodes=((2, 1.0),)))
    plbar.write_results(res, tmp_path)
    plbar.write_results(res, tmp_path)                              # same case: fine
    with pytest.raises(OutputExistsError, match="another case"):
        plbar.write_results(other, tmp_path)
    plbar.write_results(other, tmp_path, overwrite=True)
    (tmp_path / ".plbar-owner.json").unlink()                     # a folder plbar did not record as its own
    (tmp_path / "summary.json").write_text("{not json")
    with pytest.raises(OutputExistsError, match="summary.json without a plbar owner marker"):
        plbar.write_results(other, tmp_path)
    with pytest.raises(InputError, match="not a plbar.Result"):
        plbar.write_results("res", tmp_path)


# --- atomic, finite output ------------------------------------------------------------------------

def test_atomic_files_get_normal_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        p = pio.write_text(tmp_path / "a.txt", "x\n")
        assert (p.stat().st_mode & 0o777) == 0o644
        os.umask(0o027)
        p = pio.write_text(tmp_path / "b.txt", "x\n")
        assert (p.stat().st_mode & 0o777) == 0o640
    finally:
        os.umask(old)
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a.txt", "b.txt"]     # no temporary left


def test_atomic_path_failure_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        with pio.atomic_path(tmp_path / "r.csv") as tmp:
            Path(tmp).write_text("half")
            raise RuntimeError("killed")
    assert list(tmp_path.iterdir()) == []


def test_write_csv_and_json_refuse_non_finite(tmp_path):
    with pytest.raises(NonFiniteError, match=r"column 'xi' row 2 = nan"):
        pio.write_csv(tmp_path / "p.csv", ["T", "xi"], [np.array([1.0, 2.0]), np.array([0.1, np.nan])],
                      ["%g", "%g"], allow_nan=False)
    with pytest.raises(NonFiniteError, match=r"column 'T' row 1 = inf"):
        pio.write_csv(tmp_path / "p.csv", ["T"], [np.array([np.inf])], ["%g"])
    with pytest.raises(NonFiniteError, match=r"branches\[0\].xi_range\[1\] = inf"):
        pio.write_json(tmp_path / "s.json", {"branches": [{"xi_range": [0.0, float("inf")]}]})
    with pytest.raises(NonFiniteError, match=r"a\[1\] = nan"):
        pio.write_json(tmp_path / "s.json", {"a": np.array([1.0, np.nan])})
    assert list(tmp_path.iterdir()) == []
    assert issubclass(NonFiniteError, PlbarError)


def test_write_results_refuses_nan_and_writes_nothing(tmp_path):
    res = plbar.solve(plbar.Case(signatures="paper", n=3, grid=(24, 24), method="grid"))
    assert res.branches
    orb = res.branches[0].orbits[0]
    orb.__dict__["dPL"] = np.nan                     # a nan slipped through the solver
    with pytest.raises(NonFiniteError, match=r"paths.csv: dPL\[0\]"):
        plbar.write_results(res, tmp_path / "o")
    assert not (tmp_path / "o").exists() or list((tmp_path / "o").iterdir()) == []


def test_cli_non_finite_result_is_exit_1(capsys, tmp_path, monkeypatch):
    import plbar.app.run as run

    def boom(*a, **k):
        raise NonFiniteError("paths.csv: xi[0] = nan is not finite")

    monkeypatch.setattr(run, "write_csv", boom)
    code, err = _cli(capsys, ["run", *PAPER, "--out", str(tmp_path / "o"), "--grid", "24", "24", "--no-plot", "-q",
                              "--method", "grid"])
    lines = [x for x in err.strip().split("\n") if not x.startswith("plbar: warning: ")]
    assert code == 1 and lines == ["plbar: failed: paths.csv: xi[0] = nan is not finite"]


# --- warnings -------------------------------------------------------------------------------------

def test_coarse_grid_warns(capsys, tmp_path):
    with pytest.warns(CoarseGridWarning, match=r"grid = \(10, 12\) is coarse"):
        plbar.solve(plbar.Case(signatures="paper", n=3, grid=(10, 12), method="grid"))
    code, err = _cli(capsys, ["run", *PAPER, "--out", str(tmp_path / "o"), "--grid", "10", "10", "--no-plot", "-q",
                              "--method", "grid"])
    assert code == 0
    assert "plbar: warning: grid = (10, 10) is coarse" in err
    assert all(line.startswith("plbar: warning: ") for line in err.strip().split("\n"))


def test_short_branch_warns():
    with pytest.warns(CoarseGridWarning, match="fewer than 3 points"):
        plbar.solve(plbar.Case(signatures="paper", n=5, grid=(8, 8), method="grid"))


def test_no_warning_on_fine_grid():
    """A grid of >= 20 points per axis whose branches all have >= 3 points: neither warning is issued."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoarseGridWarning)
        plbar.Case(grid=(20, 20))               # building a case never warns
        res = plbar.solve(plbar.Case(signatures="paper", n=3, grid=(40, 40)))
    assert res.branches and min(len(b) for b in res.branches) >= 3
    with pytest.warns(CoarseGridWarning):       # the same case, coarser: the check is live
        plbar.solve(plbar.Case(signatures="paper", n=3, grid=(12, 12)))
