"""The figures of the README and the documentation are current: each embedded image was made by
``docs/make_figures.py`` with today's plotting code and command (its PNG stamp; nothing is recomputed)."""

import re
import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MAKE = runpy.run_path(str(ROOT / "docs" / "make_figures.py"))
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def embedded() -> list[str]:
    """The names of the images in docs/img that the README and the documentation's pages show."""
    names = set()
    for page in PAGES:
        names |= set(re.findall(r"!\[[^\]]*\]\((?:docs/)?img/([^)\s]+)\)", page.read_text()))
    return sorted(names)


def test_the_script_makes_every_embedded_image():
    names = embedded()
    assert "frequency_response.png" in names and len(names) >= 10
    assert set(names) <= set(MAKE["figures"]()), set(names) - set(MAKE["figures"]())


@pytest.mark.parametrize("name", embedded())
def test_embedded_image_is_current(name):
    from PIL import Image

    path = ROOT / "docs" / "img" / name
    assert path.is_file(), f"docs/img/{name} is missing: run python docs/make_figures.py {name}"
    with Image.open(path) as im:
        text = dict(im.text)
    fix = f"run python docs/make_figures.py {name}"
    assert MAKE["HASH_KEY"] in text, f"docs/img/{name} was not made by docs/make_figures.py: {fix}"
    assert text[MAKE["HASH_KEY"]] == MAKE["visuals_hash"](), (
        f"docs/img/{name} is stale: plbar/visuals changed since it was drawn; {fix}")
    assert text[MAKE["COMMAND_KEY"]] == MAKE["figures"]()[name], (
        f"docs/img/{name} is stale: its command in docs/make_figures.py changed; {fix}")
