"""Regenerate every figure the README and the documentation embed (``docs/img/*.png``) from the code.

Each figure is made by the command of :data:`RECIPES` (``plbar`` through its CLI, on the default cases the
pages describe), in a temporary folder, and copied into ``docs/img`` stamped with PNG text: ``plbar-visuals``,
the hash of the plotting code (:func:`visuals_hash`, every source file of ``plbar/visuals``), and
``plbar-command``, the command that made it.  ``tests/test_figures_current.py`` reads the stamps (no
recomputation) and fails when the plotting code or the command changed since: then run this script.

Usage (from the repository's root)::

    python docs/make_figures.py                  # every figure (about 15-25 min on 2 busy cores)
    python docs/make_figures.py survey.png ...   # only the recipes making these figures
    python docs/make_figures.py --list           # the figures and their commands

It lives in ``docs/`` beside the images and pages it serves (``examples/`` are user scripts, each run by the
tests); it needs the ``plot`` and ``vtk`` extras (matplotlib, pyvista for ``snapshots.png``).
"""

from __future__ import annotations

import hashlib
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IMG = ROOT / "docs" / "img"
VISUALS = ROOT / "plbar" / "visuals"
HASH_KEY, COMMAND_KEY = "plbar-visuals", "plbar-command"
PLBAR = ("python", "-m", "plbar")

#: ``(commands, {figure in docs/img: the file the commands write in their folder {out}})``; ``python`` is the running
#: interpreter; the commands run from the repository's root, one after another
RECIPES = (
    ((PLBAR + ("run", "--out", "{out}", "-q"),
      PLBAR + ("render", "--from", "{out}", "--out", "{out}/render", "--no-gif", "-q")),
     {"frequency_response.png": "frequency_response.png",
      "frequency_response_signatures.png": "frequency_response.png", "snapshots.png": "render/snapshots.png"}),
    ((PLBAR + ("survey", "--out", "{out}", "-q"),), {"survey.png": "survey.png"}),
    ((PLBAR + ("survey", "--per-element", "4", "--out", "{out}", "-q"),), {"survey_loads.png": "survey_loads.png"}),
    ((PLBAR + ("survey", "--model", "fe", "--end-mass", "0.5", "-N", "16", "--per-element", "2", "--T", "1.5", "4.5",
               "--num", "161", "--out", "{out}", "-q"),), {"survey_loads_fe.png": "survey_loads.png"}),
    ((PLBAR + ("sweep-loads", "-N", "5", "--out", "{out}", "-q"),), {"xi_T_s.png": "xi_T_s.png"}),
    ((PLBAR + ("refine", "--model", "fe", "--element", "P1", "--mass", "lumped", "-N", "8", "16", "32", "64", "128",
               "256", "--family", "T0_II/2", "--end-mass", "0.5", "--out", "{out}", "-q"),),
     {"refine_family.png": "refine_family.png", "refine_convergence.png": "refine_convergence.png"}),
    ((("python", "examples/inherent_damping.py", "{out}"),), {"xi_rayleigh.png": "xi_rayleigh.png"}),
    ((("python", "examples/restitution.py", "{out}"),), {"restitution.png": "restitution.png"}),
    ((("python", "-c", "import runpy, sys; runpy.run_path('tests/bench/damped_survey.py')['plot'](out=sys.argv[1])",
       "{out}"),), {"survey_damping.png": "survey_damping.png"}),
    # the gallery (docs/gallery.md): each example's own figure, drawn by the example itself (small: see stamp)
    *(((("python", f"examples/{script}.py", "{out}"),), {f"gallery/{script}.png": name}) for script, name in (
        ("stability_continuation", "frequency_response.png"), ("settle_from_rest", "settle_from_rest.png"),
        ("fig_2_paths", "fig2_paths.png"), ("fig_3_time_histories", "fig3_time_histories.png"),
        ("fig_4_energies", "fig4_energies.png"), ("fig_5_6_damping", "fig5_loss_damping.png"),
        ("fig_7_load_responses", "fig7_load_responses.png"), ("fig_8_xi_per_load", "fig8_xi_per_load.png"),
        ("real_motion", "survey.png"), ("impact_oscillator", "impact_oscillator.png"),
        ("cantilever_stop", "cantilever_stop.png"), ("base_excited_cantilever", "base_excited_cantilever.png"),
        ("cracked_bar", "cracked_bar.png"))),
    ((PLBAR + ("survey", "--gap", "1", "--amplitudes", "0.25", "0.5", "1", "2", "4", "8", "16", "--periods", "400",
               "--out", "{out}", "-q"),), {"survey_amplitudes.png": "survey_amplitudes.png"}),
)


def visuals_hash(folder: Path = VISUALS) -> str:
    """SHA-256 (first 16 hex digits) of every ``*.py`` of the plotting package, by name and content."""
    h = hashlib.sha256()
    for p in sorted(folder.glob("*.py")):
        h.update(p.name.encode() + b"\0" + p.read_bytes() + b"\0")
    return h.hexdigest()[:16]


def command_text(commands) -> str:
    """The commands as stamped, joined by ``&&`` (``{out}`` left as it is: the folder does not matter)."""
    return " && ".join(" ".join(c) for c in commands)


def figures() -> dict[str, str]:
    """Every figure the script makes -> the command that makes it."""
    return {fig: command_text(cmds) for cmds, files in RECIPES for fig in files}


def small(im, width: int = 1000):
    """The gallery's copy of a figure: at most ``width`` pixels wide, 256 colours (a fifth of the bytes)."""
    from PIL import Image

    im = im.convert("RGB")
    if im.width > width:
        im = im.resize((width, round(im.height * width / im.width)), Image.LANCZOS)
    return im.quantize(colors=256, method=Image.MEDIANCUT, dither=Image.NONE)


def stamp(src: Path, dest: Path, command: str, code: str) -> None:
    """Copy the PNG ``src`` to ``dest`` with the text chunks ``plbar-visuals = code``, ``plbar-command = command``
    (a figure of the gallery, ``gallery/*.png``, made :func:`small`)."""
    from PIL import Image, PngImagePlugin

    info = PngImagePlugin.PngInfo()
    dest.parent.mkdir(parents=True, exist_ok=True)
    with Image.open(src) as im:
        for k, v in im.text.items():
            if k not in (HASH_KEY, COMMAND_KEY):
                info.add_text(k, v)
        info.add_text(HASH_KEY, code)
        info.add_text(COMMAND_KEY, command)
        tmp = dest.with_suffix(".part.png")
        (small(im) if dest.parent.name == "gallery" else im).save(tmp, pnginfo=info, optimize=True)
    tmp.replace(dest)


def make(commands, files: dict, code: str) -> float:
    """Run one recipe in a temporary folder and stamp its figures into ``docs/img``; returns its seconds."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        for command in commands:
            argv = [sys.executable if a == "python" else a.replace("{out}", str(out)) for a in command]
            subprocess.run(argv, cwd=ROOT, check=True)
        for fig, name in files.items():
            stamp(out / name, IMG / fig, command_text(commands), code)
    return time.perf_counter() - t0


def main(argv) -> int:
    if "--list" in argv:
        for fig, cmd in figures().items():
            print(f"{fig:38s} {cmd}")
        return 0
    unknown = set(argv) - set(figures())
    if unknown:
        print(f"make_figures: no figure {sorted(unknown)}; --list names them", file=sys.stderr)
        return 2
    code = visuals_hash()
    t_all = time.perf_counter()
    for commands, files in RECIPES:
        if argv and not set(argv) & set(files):
            continue
        seconds = make(commands, files, code)
        print(f"{', '.join(files)}: {seconds:.0f} s  ({command_text(commands)})", flush=True)
    print(f"all in {time.perf_counter() - t_all:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
