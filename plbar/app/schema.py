"""The one schema of TOML case files: every key, its type and what it means (read by :mod:`.casefile`).

:func:`schema_table` writes it as the README's table of keys (a test keeps the two in step).
"""

from __future__ import annotations

from ..model.bar import MASSES

__all__ = ["FORMATS", "SCHEMA", "REQUIRED", "HELP", "TYPES", "schema_table"]

FORMATS = ("pvd", "xdmf", "both")

#: expected types: "int", "float" (int accepted), "str", "bool", ("choice", values), "pair", "grid", "pairs",
#: "vector" (a number or an array of numbers)
SCHEMA = {
    "": {"title": "str", "bar": "table", "load": "tables", "start": "table", "search": "table", "output": "table"},
    "bar": {"model": ("choice", ("chain", "fe", "continuum", "beam", "matrices")), "matrices": "str",
            "load_scale": "float", "n": "int", "element": ("choice", ("P1", "P2")),
            "mass": ("choice", MASSES), "length": "float", "EA": "float", "rhoA": "float",
            "m": "float", "k": "float", "grading": "float", "mesh_file": "str", "point_masses": "pairs",
            "end_mass": "float", "end_mass_absolute": "bool", "modes": "int", "rayleigh": "pair",
            "damping_ratio": "float", "damping_at": "pair", "restitution": "float", "gap": "float",
            "gravity": "float", "EI": "float", "supports": ("choice", ("clamped-free", "pinned-pinned",
                                                                          "clamped-clamped", "free-free")),
            "contact_at": "float", "crack_at": "float"},
    "load": {"node": "int", "at": "float", "amplitude": "float", "base": "float"},
    "start": {"x": "vector", "v": "vector"},
    "search": {"grid": "grid", "T1": "pair", "T2": "pair", "method": ("choice", ("continuation", "grid")),
               "signatures": ("choice", ("default", "paper", "all"))},
    "output": {"dir": "str", "vtk": "bool", "format": ("choice", FORMATS), "render": "bool", "field": "str",
               "periods": ("choice", (1, 2)), "steps": "int", "snapshots": "int", "gif": "bool",
               "branch": "int", "index": "int", "overwrite": "bool"},
}
REQUIRED = ("bar",)

#: what each key means (the README's table is :func:`schema_table`; a test keeps the two and SCHEMA in step)
HELP = {
    "": {"title": "a label for the case (optional)", "bar": "the bar (required)",
         "load": "one `[[load]]` table per force (optional: without one, the default load: DOF 1 of the chain, "
                 "a unit force at s = L/2 of an FE bar)",
         "start": "the motion's start (optional: without it, at rest in the static equilibrium)",
         "search": "where to look for paths (optional)", "output": "what to write (optional)"},
    "bar": {"model": "the paper's chain of N masses (L = N), a finite-element bar, or the exact uniform bar by "
                     "characteristics (survey, export, render; n its steps per L/c; with Rayleigh damping by exact "
                     "modes per contact state, `modes` of them, default 1024: survey only), an Euler-Bernoulli beam "
                     "against a stop (`beam`: `EI`, `supports`, `contact_at`; run and survey), or another FE "
                     "program's structure (`matrices`: run and survey); required",
            "matrices": "a structure file (.npz of `M`, `K`, the contact `r` or integer `contact`, the load `q`; "
                        "optional `C` of Rayleigh form or `rayleigh`, `restitution`, `x`), relative to the TOML "
                        "file; `model = \"matrices\"` only",
            "load_scale": "a factor on the structure file's load `q` [1]; `model = \"matrices\"` only",
            "n": "masses of the chain / elements of the FE bar [5 / 8]; not with `mesh_file`",
            "element": "FE element [P1]; FE only",
            "mass": "FE mass matrix [lumped]; FE only; `redistributed` needs `end_mass` > 0",
            "length": "bar length L, in any consistent units (see Units) [1]; FE or continuum, not with `mesh_file`",
            "EA": "axial stiffness E A, a force (N in SI) [1]; FE or continuum",
            "rhoA": "mass per length rho A (kg/m in SI) [1]; FE or continuum", "m": "chain mass [1]; chain only",
            "k": "chain spring stiffness [1]; chain only",
            "grading": "last / first element length [1]; FE only, not with `mesh_file`",
            "mesh_file": "a 1D line mesh (meshio), relative to the TOML file; FE only",
            "point_masses": "extra point masses m at FE vertices x; FE only",
            "end_mass": "a rigid mass on the contact node, as a fraction of the bar's mass [0]",
            "end_mass_absolute": "`true`: `end_mass` is the mass itself [false]; needs `end_mass` > 0",
            "modes": "keep the lowest modes of each state (locating paths only, never for xi_eq) [all]; "
                     "the damped continuum: its exact modes per contact state [1024]",
            "rayleigh": "inherent damping C = alpha M + beta K, `[alpha, beta]` >= 0 [none]",
            "damping_ratio": "the Rayleigh damping with this ratio at the two periods of `damping_at`; not with "
                             "`rayleigh`",
            "damping_at": "the two periods `[T_A, T_B]` where `damping_ratio` holds",
            "restitution": "coefficient of restitution e of the contact, 0 <= e <= 1 (Newton's impact law; "
                           "run's responses then rebound: R in their signatures; sweep-loads and refine need 0) [0]",
            "gap": "the stop's distance from the contact at rest, d (the contact stays <= d): > 0 a clearance, < 0 an "
                   "interference held by the stop; the response then depends on the amplitude over the gap [0]",
            "gravity": "a uniform acceleration g along the bar, > 0 towards the stop: the weight of the bar's masses "
                       "under g, beside the harmonic load; the bar starts in its static equilibrium [0]",
            "EI": "model = \"beam\": the bending stiffness E I [1]",
            "supports": "model = \"beam\": clamped-free (a cantilever), pinned-pinned or clamped-clamped; a cracked "
                        "FE bar (`crack_at`): clamped-free or clamped-clamped; an FE bar with no support (a free "
                        "body, dropped with `gravity`): free-free [clamped-free]",
            "contact_at": "model = \"beam\": the stop's position on the beam [the tip of a cantilever, else "
                          "mid-span]",
            "crack_at": "model = \"fe\": a breathing crack at this vertex: the contact is the crack's faces (open in "
                        "tension), the end x = L is free [none: the stop at x = L]"},
    "load": {"node": "a force on free DOF K (1-based from the clamp); or `at`",
             "at": "a point force at position s in (0, L]; or `node`",
             "amplitude": "its amplitude, a force (N in SI) [1]",
             "base": "instead of a force: the support's acceleration amplitude along the bar (> 0 towards the "
                     "stop), the load -M t a_g cos(W t); responses relative to the support"},
    "start": {"x": "the displacements at t = 0: a number (every DOF: a bar moved as a whole, a body dropped from "
                   "x = -h) or one per DOF (from the clamp) [0]; the survey's motions start there",
              "v": "the velocities at t = 0, as `x` [0]"},
    "search": {"grid": "scan grid over (T1, T2) [200, 200]",
               "T1": "search range of T1 [(0, T0_I/2]]", "T2": "search range of T2 [(0, T0_II/2]]",
               "method": "branches by continuation from the scan, or by linking its crossings [continuation]",
               "signatures": "every signature found without the user (the paper's class, those reached from it, "
                             "what a simulation from rest settles on), the paper's class only, or also the survey's "
                             "simulation and orbits up to m = 8 [default]"},
    "output": {"dir": "output folder, relative to the current directory (`--out` overrides it)",
               "vtk": "also write the ParaView time series of one response [false]",
               "format": "ParaView file format [pvd]", "render": "also render pictures of it [false]",
               "field": "the field to colour by [displacement]", "periods": "periods written [1]",
               "steps": "time steps per period, >= 4 [40]", "snapshots": "snapshots, >= 1 [4]",
               "gif": "an animated GIF too [true]", "branch": "branch id [the largest xi_eq]",
               "index": "point along the branch; negative counts from its end, -1 is its last [the largest xi_eq]",
               "overwrite": "replace what another command or case owns in the folder [false]"},
}
TYPES = {"int": "integer", "float": "number", "str": "string", "bool": "boolean", "pair": "[low, high]",
         "grid": "[N1, N2]", "pairs": "[[x, m], ...]", "vector": "number or [numbers]", "table": "table",
         "tables": "array of tables"}


def schema_table() -> str:
    """The README's table of case-file keys, generated from :data:`SCHEMA` and :data:`HELP` (markdown)."""
    rows = ["| section | key | type | meaning [default] |", "|---|---|---|---|"]
    for sec, keys in SCHEMA.items():
        name = "(top level)" if not sec else ("[[load]]" if sec == "load" else f"[{sec}]")
        for key, kind in keys.items():
            t = " \\| ".join(f"`{v}`" for v in kind[1]) if isinstance(kind, tuple) else TYPES[kind]
            rows.append(f"| {name} | `{key}` | {t} | {HELP[sec][key]} |")
    return "\n".join(rows)
