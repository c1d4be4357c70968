"""TOML case files: ``load_case(path) -> (Case, OutputSettings)`` and ``dump_case``.

A case file::

    title = "paper Sec. 4.1"            # optional
    [bar]                               # required
    model = "chain"                     # chain | fe | continuum
    n = 5
    [[load]]                            # optional: without one, the default load of Case (as the CLI)
    node = 1                            # free DOF K (1-based from the clamp) ...
    amplitude = 1.0
    [[load]]
    at = 1.25                           # ... or a point force at s in (0, L]
    [start]                             # optional: the motion's start (default: at rest)
    x = -0.5                            # every DOF, or one number per DOF
    [search]                            # optional
    grid = [200, 200]
    T1 = [0.0, 5.0]
    T2 = [0.0, 11.0]
    [output]                            # optional
    dir = "out/sec41"                   # relative to the current directory
    vtk = true

``[bar]`` keys: ``model, n, element, mass, length, EA, rhoA, m, k, grading,
mesh_file`` (relative to the TOML file), ``point_masses = [[x, m], ...]``,
``end_mass`` (a point mass on the contact node, as a fraction of the bar's mass;
``end_mass_absolute = true`` for the mass itself; both models),
``modes`` (modal truncation: the lowest modes of each state),
``rayleigh = [alpha, beta]`` (inherent damping ``C = alpha M + beta K``; default none)
or ``damping_ratio = XI`` with ``damping_at = [T_A, T_B]`` (the same from one ratio at
two periods, :func:`plbar.rayleigh_from_ratio`), ``restitution = E`` (the contact's coefficient of
restitution, ``0 <= E <= 1``; default 0, the paper's plastic impact), ``gap = D`` (the stop's distance from
the contact at rest: ``> 0`` a clearance, ``< 0`` an interference; default 0, the paper), ``gravity = G`` (a
uniform acceleration along the bar, ``> 0`` towards the stop: the weight of the bar's masses under ``G``; default 0).
Every mistake raises :class:`plbar.errors.CaseFileError` with one line naming
the file, the section and the key.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from pathlib import Path

from ..errors import CaseFileError, InputError
from ..model import rayleigh_from_ratio
from .schema import HELP, REQUIRED, SCHEMA, schema_table

__all__ = ["OutputSettings", "load_case", "loads_case", "dump_case", "schema_table", "SCHEMA", "HELP"]

try:  # Python >= 3.11
    import tomllib as _toml
except ModuleNotFoundError:  # pragma: no cover - Python 3.10 with tomli installed
    try:
        import tomli as _toml
    except ModuleNotFoundError:
        _toml = None

@dataclass(frozen=True)
class OutputSettings:
    """The ``[output]`` section.

    Attributes
    ----------
    dir : str, optional
        Output folder (relative to the current directory); None: the CLI's ``--out``.
    vtk : bool
        Write the ParaView time series of one response (:func:`plbar.app.write_response`).
    format : {"pvd", "xdmf", "both"}
    render : bool
        Render PNG snapshots (and a GIF) with :func:`plbar.visuals.render`.
    field : str
        Field to colour by.
    periods, steps : int
        Periods (1 or 2) and steps per period of the time series.
    snapshots : int
    gif : bool
    branch, index : int, optional
        Which response to export (default: the largest ``xi_eq``).
    overwrite : bool
    """

    dir: str | None = None
    vtk: bool = False
    format: str = "pvd"
    render: bool = False
    field: str = "displacement"
    periods: int = 1
    steps: int = 40
    snapshots: int = 4
    gif: bool = True
    branch: int | None = None
    index: int | None = None
    overwrite: bool = False

    def __post_init__(self):
        for key, lo in (("steps", 4), ("snapshots", 1), ("branch", 0), ("index", 0)):
            v = getattr(self, key)
            if v is not None and v < lo:
                raise InputError(f"{key} = {v} is not allowed; it must be >= {lo}")


def _fmt(v) -> str:
    """A value as TOML would spell it (for messages and dumps)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_fmt(x)}" for k, x in v.items()) + "}"
    return str(v)


def _tname(v) -> str:
    return {bool: "boolean", int: "integer", float: "float", str: "string", list: "array",
            dict: "table"}.get(type(v), type(v).__name__)


def _or(values) -> str:
    vals = [str(v) for v in values]
    return vals[0] if len(vals) == 1 else ", ".join(vals[:-1]) + " or " + vals[-1]


class _Ctx:
    """Builds one-line messages: ``file: [section] key = value ...``."""

    def __init__(self, fname: str):
        self.fname = fname

    def err(self, section: str, msg: str) -> CaseFileError:
        where = f"[{section}] " if section else ""
        return CaseFileError(f"{self.fname}: {where}{msg}")

    def keys(self, section: str, table: dict) -> None:
        allowed = SCHEMA[section]
        for key in table:
            if key not in allowed:
                close = difflib.get_close_matches(key, list(allowed), n=1, cutoff=0.6)
                hint = f'did you mean "{close[0]}"? ' if close else ""
                raise self.err(section, f'unknown key "{key}"; {hint}allowed keys: {", ".join(allowed)}')

    def value(self, section: str, key: str, v):
        kind = SCHEMA[section][key]
        bad = f"{key} = {_fmt(v)}"
        if isinstance(kind, tuple):
            allowed = kind[1]
            if isinstance(allowed[0], int) and (isinstance(v, bool) or not isinstance(v, int)):
                raise self.err(section, f"{bad} has the wrong type ({_tname(v)}); expected an integer: {_or(allowed)}")
            if isinstance(allowed[0], str) and not isinstance(v, str):
                raise self.err(section, f"{bad} has the wrong type ({_tname(v)}); expected a string: "
                                        f"{_or(_fmt(a) for a in allowed)}")
            if v not in allowed:
                raise self.err(section, f"{bad} is not allowed; choose {_or(allowed)}")
            return v
        if kind == "int":
            if isinstance(v, bool) or not isinstance(v, int):
                raise self.err(section, f"{bad} has the wrong type ({_tname(v)}); expected an integer")
            return v
        if kind == "float":
            return self._number(section, bad, v)
        if kind == "str":
            if not isinstance(v, str):
                raise self.err(section, f"{bad} has the wrong type ({_tname(v)}); expected a string")
            return v
        if kind == "bool":
            if not isinstance(v, bool):
                raise self.err(section, f"{bad} has the wrong type ({_tname(v)}); expected true or false")
            return v
        if kind in ("pair", "grid"):
            what = "two integers [N1, N2]" if kind == "grid" else "a pair of numbers [low, high]"
            if not isinstance(v, list) or len(v) != 2:
                raise self.err(section, f"{bad} must be {what}")
            if kind == "grid":
                if any(isinstance(x, bool) or not isinstance(x, int) for x in v):
                    raise self.err(section, f"{bad} has the wrong type; expected {what}")
                return tuple(v)
            return tuple(self._number(section, bad, x) for x in v)
        if kind == "pairs":
            if not isinstance(v, list):
                raise self.err(section, f"{bad} must be an array of [x, m] pairs")
            out = []
            for item in v:
                if not isinstance(item, list) or len(item) != 2:
                    raise self.err(section, f"{bad} must be an array of [x, m] pairs; got {_fmt(item)}")
                out.append(tuple(self._number(section, bad, x) for x in item))
            return tuple(out)
        if kind == "vector":
            if isinstance(v, list):
                return tuple(self._number(section, bad, x) for x in v)
            return self._number(section, bad, v)
        raise AssertionError(kind)  # pragma: no cover

    def _number(self, section, bad, v) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.err(section, f"{bad} has the wrong type ({_tname(v)}); expected a number")
        if not math.isfinite(v):
            raise self.err(section, f"{bad} is not allowed; it must be finite")
        return float(v)


def _table(ctx: _Ctx, data: dict, name: str) -> dict:
    t = data.get(name, {})
    if not isinstance(t, dict):
        raise ctx.err("", f"{name} = {_fmt(t)} must be a table [{name}]")
    ctx.keys(name, t)
    return {k: ctx.value(name, k, v) for k, v in t.items()}


def _loads(ctx: _Ctx, loads) -> tuple[list, list, float]:
    """The ``[[load]]`` tables as nodal forces, point forces and a base acceleration (none: the default load of
    :class:`Case`)."""
    if not isinstance(loads, list) or not all(isinstance(x, dict) for x in loads):
        raise ctx.err("", "load must be an array of tables: write each force as [[load]] with node = K or at = S")
    nodes, points, base = [], [], 0.0
    for i, raw in enumerate(loads, 1):
        ctx.keys("load", raw)
        ld = {k: ctx.value("load", k, v) for k, v in raw.items()}
        if "base" in ld:
            if len(ld) > 1:
                raise ctx.err(f"load #{i}", "base = A (the support's acceleration) stands alone in its [[load]]")
            base += ld["base"]
            continue
        if ("node" in ld) == ("at" in ld):
            raise ctx.err(f"load #{i}", "give exactly one of node = K (a free DOF) or at = S (a position), or "
                          "base = A (a shaking support)")
        amp = ld.get("amplitude", 1.0)
        (nodes if "node" in ld else points).append((ld["node"] if "node" in ld else ld["at"], amp))
    return nodes, points, base


def _mesh_path(ctx: _Ctx, name: str, base: Path | None, key: str = "mesh_file") -> str:
    """A file named by the case (``mesh_file``, ``matrices``) relative to the case file's folder; it must exist."""
    mf = Path(name)
    if not mf.is_absolute() and base is not None:
        mf = base / mf
    if not mf.is_file():
        raise ctx.err("bar", f"{key} = {_fmt(name)} does not exist (looked for {str(mf)!r})")
    return str(mf)


def _damping_keys(ctx: _Ctx, bar: dict) -> None:
    """``damping_ratio`` + ``damping_at`` -> ``rayleigh`` (in place); the two ways exclude each other."""
    if "damping_ratio" not in bar and "damping_at" not in bar:
        return
    if "rayleigh" in bar:
        raise ctx.err("bar", "give rayleigh = [alpha, beta] or damping_ratio with damping_at, not both")
    if "damping_ratio" not in bar or "damping_at" not in bar:
        raise ctx.err("bar", "damping_ratio = XI needs damping_at = [T_A, T_B] (the two periods where the "
                             "Rayleigh damping has the ratio XI), and the other way round")
    try:
        bar["rayleigh"] = rayleigh_from_ratio(bar.pop("damping_ratio"), *bar.pop("damping_at"))
    except InputError as exc:
        raise ctx.err("bar", str(exc)) from None


def loads_case(text: str, fname: str = "<string>", base: Path | None = None):
    """Parse case-file text; see :func:`load_case`.  ``base`` resolves ``mesh_file``."""
    from .case import Case

    ctx = _Ctx(fname)
    if _toml is None:  # pragma: no cover
        raise CaseFileError(f"{fname}: reading TOML needs Python >= 3.11 or the 'tomli' package")
    try:
        data = _toml.loads(text)
    except _toml.TOMLDecodeError as exc:
        raise CaseFileError(f"{fname}: invalid TOML: {' '.join(str(exc).split())}") from None
    ctx.keys("", data)
    title = data.get("title", "")
    if not isinstance(title, str):
        raise ctx.err("", f"title = {_fmt(title)} has the wrong type ({_tname(title)}); expected a string")
    bar = _table(ctx, data, "bar")                 # every type first, then what is missing
    nodes, points, shake = _loads(ctx, data.get("load", []))
    search = _table(ctx, data, "search")
    start = {f"start_{k}": v for k, v in _table(ctx, data, "start").items()}
    out = _table(ctx, data, "output")
    for sec in REQUIRED:
        if sec not in data:
            raise ctx.err("", f"missing required section [{sec}]")
    if "model" not in bar:
        raise ctx.err("bar", 'missing required key "model"; choose "chain", "fe", "continuum", "beam" or "matrices"')
    for key in ("mesh_file", "matrices"):
        if key in bar:
            bar[key] = _mesh_path(ctx, bar[key], base, key)
    _damping_keys(ctx, bar)
    try:        # Case is the one validator of values (ranges, the mesh, the load against the bar)
        case = Case(load_nodes=tuple(nodes), load_points=tuple(points), label=title, base=shake, **bar, **search,
                    **start)
    except InputError as exc:
        raise CaseFileError(f"{fname}: {exc}") from None
    try:
        settings = OutputSettings(**out)
    except InputError as exc:
        raise ctx.err("output", str(exc)) from None
    return case, settings


def load_case(path):
    """Read a TOML case file.

    Parameters
    ----------
    path : path
        The ``.toml`` file; ``mesh_file`` inside it is relative to its folder.

    Returns
    -------
    case : Case
    output : OutputSettings

    Raises
    ------
    CaseFileError
        One line naming the file, section and key: unknown key (with the
        closest allowed one), wrong type, value not allowed, missing section.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise CaseFileError(f"{path.name}: cannot read the case file: {exc.strerror or exc}") from None
    return loads_case(text, path.name, path.parent)


def _bar_keys(case) -> tuple:
    """The ``[bar]`` keys :func:`dump_case` writes beside ``model`` and ``n``, by model."""
    if case.model == "matrices":
        return ()
    if case.model == "chain":
        return ("m", "k")
    if case.model == "beam":
        return ("length", "EI", "rhoA", "supports", "contact_at")
    crack = ("crack_at",) if case.crack_at is not None else ()
    supports = ("supports",) if crack or case.supports != "clamped-free" else ()
    return ("element", "mass", "length", "EA", "rhoA", "grading") + crack + supports


def dump_case(case, output: OutputSettings | None = None) -> str:
    """The TOML text of ``case`` (and ``output`` if given); ``load_case`` reads it back equal."""
    lines = []
    if case.label:
        lines.append(f"title = {_fmt(case.label)}")
        lines.append("")
    lines.append("[bar]")
    lines.append(f"model = {_fmt(case.model)}")
    if case.model == "matrices":
        lines.append(f"matrices = {_fmt(str(case.matrices))}")
        if case.load_scale != 1.0:
            lines.append(f"load_scale = {_fmt(float(case.load_scale))}")
    if case.n is not None:
        lines.append(f"n = {int(case.n)}")
    for k in _bar_keys(case):
        lines.append(f"{k} = {_fmt(getattr(case, k))}")
    if case.model == "fe" and case.mesh_file:
        lines.append(f"mesh_file = {_fmt(str(case.mesh_file))}")
    if case.model == "fe" and case.point_masses:
        lines.append(f"point_masses = {_fmt([list(p) for p in case.point_masses])}")
    if case.end_mass != 0 or case.end_mass_absolute:
        lines.append(f"end_mass = {_fmt(float(case.end_mass))}")
        lines.append(f"end_mass_absolute = {_fmt(bool(case.end_mass_absolute))}")
    if case.modes is not None:
        lines.append(f"modes = {int(case.modes)}")
    if case.rayleigh is not None:
        lines.append(f"rayleigh = {_fmt([float(x) for x in case.rayleigh])}")
    if case.restitution:
        lines.append(f"restitution = {_fmt(float(case.restitution))}")
    if case.gap:
        lines.append(f"gap = {_fmt(float(case.gap))}")
    if case.gravity:
        lines.append(f"gravity = {_fmt(float(case.gravity))}")
    for k, a in case.load_nodes:
        lines += ["", "[[load]]", f"node = {int(k)}", f"amplitude = {_fmt(float(a))}"]
    if case.base:
        lines += ["", "[[load]]", f"base = {_fmt(float(case.base))}"]
    for s, a in case.load_points:
        lines += ["", "[[load]]", f"at = {_fmt(float(s))}", f"amplitude = {_fmt(float(a))}"]
    start = [f"{k} = {_fmt(list(v) if isinstance(v, tuple) else float(v))}"
             for k, v in (("x", case.start_x), ("v", case.start_v)) if v is not None]
    lines += ["", "[start]", *start] if start else []
    lines += ["", "[search]", f"grid = {_fmt(list(case.grid))}"]
    for k in ("T1", "T2"):
        v = getattr(case, k)
        if v is not None:
            lines.append(f"{k} = {_fmt([float(x) for x in v])}")
    if output is not None:
        default = OutputSettings()
        body = [f"{k} = {_fmt(getattr(output, k))}" for k in OutputSettings.__dataclass_fields__
                if getattr(output, k) != getattr(default, k) and getattr(output, k) is not None]
        if body:
            lines += ["", "[output]"] + body
    return "\n".join(lines) + "\n"
