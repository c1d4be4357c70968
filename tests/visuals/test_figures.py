"""Every example figure script runs and draws something (not a blank canvas)."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SCRIPTS = sorted(EXAMPLES.glob("fig_*.py"))


def test_every_figure_family_has_a_script():
    names = " ".join(p.stem for p in SCRIPTS)
    for k in ("fig_2", "fig_3", "fig_4", "fig_5_6", "fig_7", "fig_8", "fig_9"):
        assert k in names


#: the longest scripts run with the slow tests (fig_2 keeps the scripts' path in the default run)
SLOW = {"fig_3_time_histories", "fig_4_energies", "fig_5_6_damping", "fig_7_load_responses", "fig_8_xi_per_load",
        "fig_9_xi_position"}


@pytest.mark.parametrize("script", [pytest.param(s, marks=pytest.mark.slow) if s.stem in SLOW else s
                                    for s in SCRIPTS], ids=lambda p: p.stem)
def test_figure_script(script, tmp_path):
    pytest.importorskip("matplotlib")
    env = {**os.environ, "MPLBACKEND": "agg", "PLBAR_GRID": "60,60", "PLBAR_PER_ELEMENT": "2"}
    r = subprocess.run([sys.executable, str(script), str(tmp_path)], env=env, capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    pngs = sorted(tmp_path.glob("*.png"))
    assert pngs and len(pngs) == len(sorted(tmp_path.glob("*.pdf")))
    import matplotlib.image as mpimg

    for png in pngs:
        img = mpimg.imread(png)[..., :3]
        assert img.shape[0] > 200 and img.shape[1] > 300
        nonwhite = np.mean(np.any(img < 0.95, axis=-1))
        colours = np.unique((img.reshape(-1, 3) * 255).astype(np.uint8), axis=0).shape[0]
        assert nonwhite > 0.02, f"{png.name} is (nearly) blank"
        assert img.std() > 0.05 and colours > 20, f"{png.name} has no content"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
