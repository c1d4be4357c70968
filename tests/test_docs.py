"""The documentation site: every page reachable, every example a page, the current option spellings, and the
Sphinx build with warnings as errors."""

import argparse
import importlib.util
import re
import runpy
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = [ROOT / "README.md", *sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts)]


def test_readme_keeps_its_two_commands_and_links_to_pages_that_exist():
    text = (ROOT / "README.md").read_text()
    block = text.split("```bash\n", 1)[1].split("```", 1)[0].splitlines()
    assert block[1] == ('python3 -m venv .venv && . .venv/bin/activate && pip install -e ".[test]" && '
                        'python -m pytest -q -m "not slow"')
    links = re.findall(r"\]\((docs/[^)#]+)", text)
    assert len(links) >= 15
    for link in links:
        assert (ROOT / link).is_file(), link


def test_the_readme_python_example_prints_every_branch_of_every_signature(default_run, tmp_path, monkeypatch,
                                                                           capsys):
    """The README's Python example runs as it is written and prints one line per branch: every branch of the
    paper's class (``1P``) and of every other signature, with its T range, largest xi_eq and stable points; its
    files are written and its one response is periodic at round-off."""
    from collections import Counter

    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert len(blocks) == 1 and len(blocks[0].strip().splitlines()) <= 12, "one short Python example"
    monkeypatch.chdir(tmp_path)
    exec(compile(blocks[0], "README.md", "exec"), {"__name__": "readme"})
    lines = capsys.readouterr().out.splitlines()
    rows = [line.split() for line in lines if " T " in line and "stable at" in line]
    expected = Counter(b.label for b in default_run.branches)
    assert Counter(row[0] for row in rows) == expected
    assert rows[0][0] == "1P", "the paper's class first"
    assert len(default_run.paper) >= 1 and set(expected) - {"1P"}, "the paper's class and other signatures"
    for row in rows:                                      # T from .. to .., the largest xi_eq, stable k of n
        assert float(row[2]) <= float(row[4]) and 0 <= float(row[7]) < 1
        assert 0 <= int(row[10]) <= int(row[12])
    assert {p.name for p in (tmp_path / "results-py").iterdir()} >= {"paths.csv", "summary.json"}
    T1, phi, xi, defect = map(float, lines[-1].split())
    assert abs(T1 - 2.3874) < 1e-3 and 0 < xi < 1 and defect < 1e-10


def test_every_example_is_a_page_of_the_site():
    index = (DOCS / "examples" / "index.md").read_text()
    for script in sorted((ROOT / "examples").glob("*.py")):
        page = DOCS / "examples" / f"{script.stem}.md"
        assert page.is_file() and f"../../examples/{script.name}" in page.read_text(), script.name
        assert f"\n{script.stem}\n" in index, script.stem


def front_doors():
    """The subpackages (and the rooms of a layer split into rooms) whose ``__init__`` the API documents."""
    from plbar.util import layout

    doors = {m for m in layout.modules() if m.count(".") <= 1 or m.split(".")[1] in layout.ROOMS}
    return {m for m in doors if (layout.modules()[m].name == "__init__.py")} - {"plbar.cli"}


def test_every_front_door_has_an_api_page():
    doors = front_doors()
    assert doors <= {p.stem for p in (DOCS / "api").glob("plbar*.md")}, doors


def test_the_api_index_lists_every_page_with_its_front_doors_summary():
    conf = runpy.run_path(str(DOCS / "conf.py"))     # the index's table is made by conf.py from these two
    entries = conf["api_entries"]((DOCS / "api" / "index.md").read_text())
    assert len(entries) == len(set(entries)), entries
    assert set(entries) == {p.stem for p in (DOCS / "api").glob("plbar*.md")} >= front_doors(), entries
    for name in entries:
        line = conf["summary"](name)
        assert len(line) > 20 and line.endswith("."), f"{name}: no one-line summary in its docstring: {line!r}"


def old_spellings():
    """The old option spellings the parser still takes: a second long name (``--n`` of ``-N/--elements``) or an
    option hidden from the help of every command that has it (``--dest``); read from the parser, so it stays
    current."""
    from plbar.cli.main import build_parser

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    old, shown, hidden = set(), set(), set()
    for parser in sub.choices.values():
        for action in parser._actions:
            names = [s for s in action.option_strings if s.startswith("--")]
            old.update(names[1:])
            (hidden if action.help == argparse.SUPPRESS else shown).update(names)
    return old | (hidden - shown)


def test_the_readme_and_the_docs_use_the_current_option_spellings():
    old = old_spellings()
    assert {"--at", "--n", "--dest"} <= old, old
    pattern = re.compile(r"(?<![\w-])(" + "|".join(re.escape(s) for s in sorted(old)) + r")(?![\w-])")
    for page in PAGES:
        text = page.read_text()
        if page.name == "cli.md":                                  # the one sentence that lists them
            text = re.sub(r"Old spellings \([^)]*\) still work", "", text)
        for n, line in enumerate(text.splitlines(), 1):
            assert not pattern.search(line), f"{page.relative_to(ROOT)}:{n}: {line}"
        for command in re.findall(r"plbar (?:export|render)\b[^`\n]*", text):   # the run read: --from, not --out
            assert "--out" not in command or "--from" in command, f"{page.relative_to(ROOT)}: {command}"


def prose(text):
    """``text`` without its fenced code blocks, inline code and math."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return re.sub(r"`+[^`]*`+|\$\$.*?\$\$|\$[^$\n]+\$", "", text, flags=re.S)


def test_formulas_are_math_not_unicode_and_typeset_by_the_shipped_mathjax():
    for page in PAGES:
        for line in prose(page.read_text()).splitlines():
            found = re.findall(r"[\u0370-\u03ff\u00b2\u00b3\u1d40\u207b\u2070-\u209f\u2211\u221a\u222b]", line)
            assert not found, f"{page.relative_to(ROOT)}: {found} outside $...$ in: {line.strip()[:120]}"
    conf = runpy.run_path(str(DOCS / "conf.py"))
    assert {"dollarmath", "amsmath"} <= set(conf["myst_enable_extensions"])
    assert (DOCS / "_static" / conf["mathjax_path"]).is_file()         # offline: no CDN


@pytest.mark.slow
@pytest.mark.skipif(any(importlib.util.find_spec(m) is None for m in ("sphinx", "myst_parser", "numpydoc")),
                    reason='the docs extra is not installed (pip install -e ".[docs]")')
def test_the_site_builds_with_warnings_as_errors(tmp_path):
    p = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS),
                        str(tmp_path / "html")], capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    for page in ("index", "theory", "loads", "refinement", "survey", "api/plbar.studies.loads",
                 "examples/one_response"):
        assert (tmp_path / "html" / f"{page}.html").is_file(), page
    for page in ("theory", "damping", "load_structure"):            # math typeset: MathJax and no raw $ left
        html = (tmp_path / "html" / f"{page}.html").read_text()
        assert 'src="_static/mathjax/tex-chtml.js' in html and html.count('class="math') > 10, page
        text = re.sub(r"<(script|pre|code)\b.*?</\1>|<(span|div) class=\"math.*?</\2>", "", html, flags=re.S)
        assert "$" not in text, page
    index = (tmp_path / "html" / "api" / "index.html").read_text()
    rows = index.split('class="api-index', 1)[1].split("</table>", 1)[0].count("<tr")
    assert rows == len(list((DOCS / "api").glob("plbar*.md"))), rows


def test_quoted_times_are_ranges_or_say_idle_or_busy():
    """A time the README quotes is what a benchmark measured on a machine whose load varies (issue 30, item 8:
    quotes 1.5-3x low on a busy machine): each is a range (``4–8 s``) or its paragraph says idle or busy."""
    text = (ROOT / "README.md").read_text()
    quote = re.compile(r"(?<![\d.,–-])(\d+(?:[.,]\d+)?)(?:[–-]\d+(?:[.,]\d+)?)? ?(ms|s|seconds|minutes)\b")
    bad = []
    for para in re.split(r"\n\s*\n", text):
        if para.lstrip().startswith("```bash\npython3 -m venv"):
            continue                                        # the two commands
        said = "idle" in para or "busy" in para
        for m in quote.finditer(para):
            if not (said or re.search(r"[–-]", m.group(0))):
                bad.append(para[max(0, m.start() - 50):m.end()].replace("\n", " "))
    assert not bad, bad
