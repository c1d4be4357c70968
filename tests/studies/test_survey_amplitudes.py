"""The amplitude study (issue 41 item 1): the survey at every amplitude of the load, a (T, A) table and map.

Checked by the theorem it is there to expose (FORMULATION §9, homogeneity), not by plbar's numbers alone:

* at zero gap the motion is proportional to the load: every cell's ``xi_eq`` is the ``A = 1`` cell's, its loss
  ``A^2`` times (1e-9), so the map is flat in ``A``;
* with a gap ``d`` the cell ``(d, A)`` is the cell ``(lambda d, lambda A)`` with the loss times ``lambda^2``: the
  answer depends on ``A / d`` only (1e-9), and it does depend on it (``xi_eq`` changes along ``A``);
* a cell is the plain survey of the case with its load scaled (``--amplitude``): the same simulation, bit for bit.
"""

import json
from dataclasses import replace

import numpy as np
import pytest

import plbar
from plbar.cli import main
from plbar.errors import InputError
from plbar.studies.survey import AMPLITUDES, survey, survey_loads

T = [8.5, 11.8, 12.4, 13.6]
A = [0.5, 1.0, 4.0]


def _study(case, amplitudes=A):
    return survey_loads(case, T, amplitudes, periods=400, record=40, axis=AMPLITUDES)


def test_zero_gap_is_flat_in_the_amplitude():
    t = _study(plbar.Case()).table
    one = t["A"] == 1.0
    per = t["kind"][one] == "periodic"
    assert per.sum() >= 2
    for a in A:
        sel = t["A"] == a
        assert list(t["kind"][sel]) == list(t["kind"][one])
        assert np.allclose(t["xi_eq"][sel][per], t["xi_eq"][one][per], rtol=1e-9, atol=0)
        assert np.allclose(t["loss_per_T"][sel][per], a ** 2 * t["loss_per_T"][one][per], rtol=1e-9, atol=0)


def test_with_a_gap_only_the_amplitude_over_the_gap_matters():
    a = _study(plbar.Case(gap=0.5)).table
    b = _study(plbar.Case(gap=2.0), [4 * x for x in A]).table          # lambda = 4
    assert list(a["kind"]) == list(b["kind"]) and list(a["signature"]) == list(b["signature"])
    per = a["kind"] == "periodic"
    assert per.sum() >= 3
    assert np.allclose(b["xi_eq"][per], a["xi_eq"][per], rtol=1e-9, atol=1e-15)
    assert np.allclose(b["loss_per_T"][per], 16 * a["loss_per_T"][per], rtol=1e-9, atol=1e-15)
    xi = a["xi_eq"].reshape(len(A), len(T))                             # sorted by A, then T
    assert np.nanmax(np.abs(xi[-1] - xi[0])) > 1e-3                       # and it does depend on A / d


def test_a_cell_is_the_survey_of_the_scaled_load():
    case = plbar.Case(gap=0.5)
    t = _study(case, [4.0]).table
    ref = survey(replace(case, load_nodes=((1, 4.0),)), T, periods=400, record=40).table
    for c in ("kind", "loss_per_T", "xi_eq", "xi_w", "signature", "energy_residual"):
        x, y = t[c], ref[c]
        assert (np.array_equal(x, y, equal_nan=True) if x.dtype == float else list(x) == list(y)), c


def test_the_command(tmp_path, capsys):
    out = tmp_path / "amp"
    assert main(["survey", "--gap", "0.5", "--amplitudes", "1", "4", "--T-list", "9", "12", "--periods", "200",
                 "--no-plot", "--quiet", "--out", str(out)]) == 0
    rows = (out / "survey_amplitudes.csv").read_text().splitlines()
    assert rows[0].startswith("N,A,T,") and len(rows) == 1 + 4
    s = json.loads((out / "summary.json").read_text())
    assert s["amplitudes"] == [1.0, 4.0] and "worst_amplitude_per_T" in s["by_N"]["5"]
    assert main(["survey", "--amplitudes", "1", "--positions", "1", "--T-list", "9", "--out", str(tmp_path / "x"),
                 "--no-plot", "--quiet"]) == 2
    assert "two studies" in capsys.readouterr().err
    with pytest.raises(InputError, match="positive"):
        _study(plbar.Case(), [0.0])


def test_a_structure_in_memory_is_refused_by_name_with_the_way_in(tmp_path):
    """A survey's tasks rebuild the case from data: a plbar.Structure in memory says how to give it instead (it
    failed in every task with "unexpected keyword argument 'dofs'"); the structure file it names works."""
    from plbar.io import write_structure

    st = replace(plbar.Case().problem().structure, origin=None)
    with pytest.raises(InputError, match="structure file"):
        survey(plbar.Case(structure=st), [9.0], periods=100, record=10)
    f = write_structure(tmp_path / "s.npz", st)
    assert survey(plbar.Case(model="matrices", matrices=str(f)), [9.0], periods=100, record=10).table["T"].size == 1
