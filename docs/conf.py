"""Sphinx configuration: ``python -m sphinx -W -b html docs docs/_build`` (needs ``pip install ".[docs]"``)."""

import ast
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("MPLBACKEND", "agg")

from plbar import __version__  # noqa: E402
from plbar.util import layout  # noqa: E402

project = "plbar"
author = "the plbar authors"
copyright = "the plbar authors"
release = version = __version__

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.viewcode", "sphinx.ext.mathjax", "numpydoc"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "img/*.md"]
myst_enable_extensions = ["colon_fence", "dollarmath", "amsmath"]
myst_heading_anchors = 3

# API reference: every front door, members in the order of __all__; numpydoc parses the docstrings
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"
autodoc_mock_imports = ["pyvista", "vtk", "h5py", "dask", "distributed"]
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()

html_theme = "alabaster"
html_title = f"plbar {version}"
html_static_path = ["_static"]
html_css_files = ["plbar.css"]
html_theme_options = {"page_width": "min(1280px, 96vw)", "sidebar_width": "240px", "body_max_width": "none"}
# MathJax 3.2.2 (Apache-2.0, _static/mathjax/LICENSE) ships with the site: it typesets offline, no CDN
mathjax_path = "mathjax/tex-chtml.js"
highlight_language = "none"
autodoc_inherit_docstrings = False


def summary(module: str) -> str:
    """The first line of ``module``'s docstring, read from its source (nothing is imported); '' if it has none."""
    doc = ast.get_docstring(ast.parse(layout.modules()[module].read_text())) or ""
    return doc.strip().partition("\n")[0]


def api_entries(source: str) -> list:
    """The pages listed by the toctree of the API index (``api/index.md``), in its order."""
    body = source.split("```{toctree}", 1)[1].split("```", 1)[0]
    return [line.strip() for line in body.splitlines() if line.strip() and not line.lstrip().startswith(":")]


def api_index(app, docname, source):
    """``source-read``: the API index gets, after its (hidden) toctree, a table of its pages with the first line
    of each front door's docstring, generated so that it cannot go stale."""
    if docname != "api/index":
        return
    rows = "".join(f"   * - :doc:`{name} <{name}>`\n     - {summary(name)}\n" for name in api_entries(source[0]))
    source[0] += f"\n```{{eval-rst}}\n.. list-table::\n   :class: api-index\n   :widths: 1 3\n\n{rows}```\n"


def setup(app):
    app.connect("source-read", api_index)
