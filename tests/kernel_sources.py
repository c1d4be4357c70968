"""The one check that a kernel package's cache key covers every module it is compiled from (importable: tests/ is
on sys.path via conftest, as ``shared_points``)."""

import ast
from pathlib import Path


def assert_imports_covered(here: Path, sources) -> None:
    """Every module of the kernel package ``here`` is in ``sources``, and so is every module it imports from outside
    its package (numba freezes what a kernel imports: a change there must change the stamp)."""
    sources = {Path(p).resolve() for p in sources}
    assert {p.resolve() for p in here.glob("*.py")} <= sources
    for path in here.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level >= 2:
                base = here.parents[node.level - 2].joinpath(*node.module.split("."))
                targets = [base / f"{a.name}.py" for a in node.names if (base / f"{a.name}.py").exists()]
                for target in targets or [base.with_suffix(".py")]:     # a module imported from a package, or one
                    assert target.resolve() in sources, (path.name, node.module)
