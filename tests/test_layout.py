"""The house rules (``python -m plbar.util.layout``): one-way imports, no cycle, front doors, small modules."""

import subprocess
import sys
import textwrap

from plbar.util import layout


def test_the_package_keeps_the_rules():
    bad = layout.violations()
    assert bad == [], "\n".join(bad)


def test_every_subpackage_is_a_layer():
    subs = {m.split(".")[1] for m in layout.modules() if m.count(".") >= 2}
    assert subs <= set(layout.LAYERS), subs - set(layout.LAYERS)
    assert len(subs) >= 5


def test_command_prints_the_graph():
    p = subprocess.run([sys.executable, "-m", "plbar.util.layout"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "response  -> errors, util, model" in p.stdout and "0 violation(s)" in p.stdout
    assert "studies.survey     -> execution, loads, refine" in p.stdout


def _pkg(tmp_path, files: dict):
    root = tmp_path / "plbar"
    for name, text in files.items():
        f = root / name
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(textwrap.dedent(text))
    return layout.modules(root)


def test_checker_finds_a_cycle_a_back_edge_a_private_import_and_a_heavy_import(tmp_path):
    mods = _pkg(tmp_path, {
        "__init__.py": "",
        "model/__init__.py": "",
        "model/a.py": "from .b import x\n",
        "model/b.py": "from .a import y\nimport matplotlib\n",
        "response/__init__.py": "",
        "response/c.py": "from ..model.a import _hidden\n",
        "util/__init__.py": "",
        "util/d.py": "from ..paths import find_paths\n",
        "paths/__init__.py": "",
    })
    bad = "\n".join(layout.violations(mods))
    assert "import cycle: plbar.model.a -> plbar.model.b" in bad
    assert "util imports plbar.paths (paths is above util)" in bad
    assert "imports private '_hidden'" in bad
    assert "heavy import 'matplotlib'" in bad


def test_checker_finds_long_functions_and_modules(tmp_path):
    body = "".join(f"    x{i} = {i}\n" for i in range(layout.MAX_FUNCTION))
    mods = _pkg(tmp_path, {"__init__.py": "", "model/__init__.py": "",
                           "model/big.py": "def f():\n" + body + "\n" * layout.MAX_MODULE})
    bad = "\n".join(layout.violations(mods))
    assert "f() has" in bad and "(module limit" in bad


def test_studies_are_rooms_that_import_one_way_through_front_doors(tmp_path):
    assert set(layout.ROOMS["studies"]) == {m.split(".")[2] for m in layout.modules()
                                            if m.startswith("plbar.studies.")}
    mods = _pkg(tmp_path, {
        "__init__.py": "",
        "studies/__init__.py": "from .loads import x\n",
        "studies/stray.py": "",
        "studies/execution/__init__.py": "from ..loads import x\n",
        "studies/loads/__init__.py": "",
        "studies/survey/__init__.py": "",
        "studies/survey/a.py": "from ..refine.convergence import converge\nfrom .. import y\n",
        "studies/refine/__init__.py": "",
        "studies/refine/convergence.py": "from ..loads import x\n",
    })
    bad = "\n".join(layout.violations(mods))
    assert "plbar.studies.stray is in no room" in bad
    assert "room studies.execution imports plbar.studies.loads (studies.loads is above studies.execution)" in bad
    assert "go through the front door plbar.studies.refine" in bad
    assert "imports its layer's front door plbar.studies" in bad
    assert "refine/convergence.py" not in bad
