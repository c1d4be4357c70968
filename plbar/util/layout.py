"""The house rules, checked from the source: ``python -m plbar.util.layout [--modules]``.

Reads every module of the package with :mod:`ast` (nothing is imported) and
checks that

* imports between subpackages flow one way, along :data:`LAYERS` (no back-edge),
  and there is no import cycle among modules;
* a layer split into rooms (:data:`ROOMS`: ``plbar.studies`` has one subpackage per study) keeps
  every module in a room, and its rooms import one way too, each from another only through
  that room's front door (``from ..refine import converge``, never ``..refine.convergence``);
* nothing outside a subpackage imports a ``_private`` name or module from it;
* the heavy libraries (:data:`HEAVY`) are imported only where :data:`HEAVY_OK` allows;
* no module is longer than :data:`MAX_MODULE` lines and no function longer than
  :data:`MAX_FUNCTION` lines.

Prints the subpackage graph (with ``--modules`` the module graph) and the
violations; exits 1 if there are any.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

__all__ = ["LAYERS", "ROOMS", "HEAVY", "HEAVY_OK", "MAX_MODULE", "MAX_FUNCTION", "modules", "graph", "violations",
           "main"]

#: subpackages from the bottom up; each may import only from those before it (``errors`` is the base)
LAYERS = ("errors", "util", "model", "continuum", "response", "paths", "motion", "periodic", "check", "io", "visuals",
          "app", "studies", "cli")
HEAVY = ("pyvista", "vtk", "vtkmodules", "meshio", "matplotlib", "dask", "distributed", "h5py", "PIL", "numba",
         "llvmlite")
#: layers split into rooms (subpackages), from the bottom up: a room imports only from those before it
ROOMS = {"studies": ("execution", "loads", "refine", "damping", "survey", "paper")}
HEAVY_OK = {"io", "visuals", "studies.execution.executor", "util.jit", "motion.kernel", "periodic.kernel",
            "continuum.kernel"}
MAX_MODULE = 400
MAX_FUNCTION = 60
ROOT = Path(__file__).resolve().parents[1]


def modules(root: Path = ROOT) -> dict[str, Path]:
    """Module name -> file of every module under the package folder ``root``."""
    out = {}
    for p in sorted(root.rglob("*.py")):
        rel = p.relative_to(root.parent).with_suffix("")
        name = ".".join(rel.parts)
        out[name[:-len(".__init__")] if name.endswith(".__init__") else name] = p
    return out


def _resolve(mod: str, is_pkg: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = mod.split(".")
    base = base[:len(base) - node.level + (1 if is_pkg else 0)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(mod: str, path: Path):
    """(target module or package, imported names, line) of every import of ``mod``."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, (), node.lineno
        elif isinstance(node, ast.ImportFrom):
            yield _resolve(mod, path.name == "__init__.py", node), tuple(a.name for a in node.names), node.lineno


def _layer(mod: str) -> str:
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "plbar"


def graph(mods: dict[str, Path] | None = None) -> dict[str, set[str]]:
    """Module -> the plbar modules it imports (a ``from pkg import name`` of a submodule counts as that module)."""
    mods = mods or modules()
    edges: dict[str, set[str]] = {m: set() for m in mods}
    for m, p in mods.items():
        for tgt, names, _ in _imports(m, p):
            for t in [tgt] + [f"{tgt}.{n}" for n in names]:
                if t in mods and t != m and not m.startswith(t + "."):
                    edges[m].add(t)
    return edges


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in edges:
        if v not in index:
            visit(v)
    return out


def _rank(layer: str) -> int:
    return LAYERS.index(layer) if layer in LAYERS else (-1 if layer == "errors" else len(LAYERS))


def _where(p: Path) -> str:
    parts = p.parts
    return "/".join(parts[parts.index("plbar"):]) if "plbar" in parts else str(p)


def _room(mod: str) -> str | None:
    """The room of a module of a layer with rooms (None for the layer's front door or another layer)."""
    parts = mod.split(".")
    return parts[2] if len(parts) > 2 and parts[1] in ROOMS else None


def _heavy_ok(mod: str) -> bool:
    rel = ".".join(mod.split(".")[1:])
    return any(rel == ok or rel.startswith(ok + ".") for ok in HEAVY_OK)


def _room_violations(mods: dict[str, Path]) -> list[str]:
    """Rooms of a layer: every module in a room, rooms import one way and through each other's front door."""
    bad = []
    for m, p in mods.items():
        lay, room = _layer(m), _room(m)
        if lay not in ROOMS or m == f"plbar.{lay}":
            continue
        rooms = ROOMS[lay]
        if room not in rooms:
            bad.append(f"{_where(p)}: {m} is in no room of {lay} ({', '.join(rooms)}; see plbar.util.layout.ROOMS)")
            continue
        for tgt, names, line in _imports(m, p):
            if tgt == f"plbar.{lay}":
                bad.append(f"{_where(p)}:{line}: {m} imports its layer's front door plbar.{lay} (a cycle); "
                           "import from the room itself")
                continue
            for t in [tgt] + [f"{tgt}.{n}" for n in names]:
                tr = _room(t) if t in mods else None
                if tr is None or tr == room or tr not in rooms:
                    continue
                where = f"{_where(p)}:{line}"
                if rooms.index(tr) > rooms.index(room):
                    bad.append(f"{where}: room {lay}.{room} imports {t} ({lay}.{tr} is above {lay}.{room})")
                elif t != f"plbar.{lay}.{tr}":
                    bad.append(f"{where}: {m} imports {t}: go through the front door plbar.{lay}.{tr}")
    return bad


def _import_violations(mods: dict[str, Path]) -> list[str]:
    bad = []
    for m, p in mods.items():
        lay = _layer(m)
        for tgt, names, line in _imports(m, p):
            where = f"{_where(p)}:{line}"
            top = tgt.split(".")[0]
            if top in HEAVY and not _heavy_ok(m):
                bad.append(f"{where}: heavy import {tgt!r} outside {sorted(HEAVY_OK)}")
            if not tgt.startswith("plbar") or lay == "plbar":
                continue
            tl = _layer(tgt) if tgt != "plbar" else "plbar"
            if tl != lay and tl in LAYERS and lay in LAYERS and _rank(tl) > _rank(lay):
                bad.append(f"{where}: {lay} imports {tgt} ({tl} is above {lay})")
            if tl != lay:
                private = [n for n in (tgt.split(".")[2:] + list(names)) if n.startswith("_") and not n.endswith("__")]
                if private:
                    bad.append(f"{where}: {m} imports private {private[0]!r} from {tgt}")
    return bad


def _size_violations(mods: dict[str, Path]) -> list[str]:
    bad = []
    for p in mods.values():
        n = len(p.read_text().splitlines())
        if n > MAX_MODULE:
            bad.append(f"{_where(p)}: {n} lines (module limit {MAX_MODULE})")
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION:
                    bad.append(f"{_where(p)}:{node.lineno}: {node.name}() has {n} lines "
                               f"(function limit {MAX_FUNCTION})")
    return bad


def violations(mods: dict[str, Path] | None = None) -> list[str]:
    """Every breach of the house rules (empty if the package is in order)."""
    mods = mods or modules()
    cyc = [f"import cycle: {' -> '.join(c)}" for c in _cycles(graph(mods))]
    return cyc + _import_violations(mods) + _room_violations(mods) + _size_violations(mods)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    mods = modules()
    edges = graph(mods)
    if "--modules" in argv:
        for m in sorted(edges):
            print(f"{m} -> {', '.join(sorted(edges[m])) or '-'}")
    else:
        sub: dict[str, set[str]] = {}
        for m, ts in edges.items():
            sub.setdefault(_layer(m), set()).update(_layer(t) for t in ts if _layer(t) != _layer(m))
        for lay in sorted(sub, key=_rank):
            print(f"{lay:9s} -> {', '.join(sorted(sub[lay], key=_rank)) or '-'}")
        for lay, rooms in ROOMS.items():
            dep: dict[str, set[str]] = {r: set() for r in rooms}
            for m, ts in edges.items():
                if _layer(m) == lay and _room(m) in dep:
                    dep[_room(m)].update(_room(t) for t in ts if _layer(t) == lay and _room(t) not in (None, _room(m)))
            for r in rooms:
                print(f"  {lay}.{r:10s} -> {', '.join(sorted(dep[r], key=rooms.index)) or '-'}")
    bad = violations(mods)
    print(f"{len(mods)} modules, layers {' < '.join(LAYERS)}: {len(bad)} violation(s)")
    for b in bad:
        print("  " + b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
