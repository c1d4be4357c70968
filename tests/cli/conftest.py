"""The fixture the command-line tests of several files share: a cheap run folder and case file."""

import pytest

from plbar.cli import main

CASE_TOML = '[bar]\nmodel = "chain"\nn = 5\n[search]\ngrid = [30, 30]\nsignatures = "paper"\n'


@pytest.fixture(scope="module")
def cheap_run(tmp_path_factory):
    """A run folder (for export and render --from) and a cheap case file (for --case)."""
    d = tmp_path_factory.mktemp("cheap")
    assert main(["run", "--no-plot", "--signatures", "paper", "--grid", "30", "30", "-q", "--out", str(d / "run")]) == 0
    (d / "c.toml").write_text(CASE_TOML)
    return d
