"""Case.end_mass: a rigid point mass on the contact node, validated, in TOML files and summary data."""

import numpy as np
import pytest

import plbar
from plbar.app import dump_case, loads_case
from plbar.errors import CaseFileError, InputError

FE = dict(model="fe", rhoA=2.0, length=3.0)
CHAIN = dict(n=5, m=2.0)


@pytest.mark.parametrize("base,end,added", [
    (FE, dict(end_mass=0.25), 1.5),                                   # 0.25 * rhoA L
    (dict(FE, mass="consistent", element="P2"), dict(end_mass=0.25), 1.5),
    (CHAIN, dict(end_mass=0.1), 1.0),                                 # 0.1 * N m
    (FE, dict(end_mass=0.7, end_mass_absolute=True), 0.7),
    (CHAIN, dict(end_mass=0.7, end_mass_absolute=True), 0.7),
], ids=["fe-fraction", "fe-P2-consistent", "chain-fraction", "fe-absolute", "chain-absolute"])
def test_end_mass_adds_to_the_contact_diagonal(base, end, added):
    case = plbar.Case(**base, **end)
    M0 = plbar.Case(**base).problem().system.M
    M = case.problem().system.M
    assert case.end_mass_value == pytest.approx(added, rel=1e-15)
    assert M[-1, -1] - M0[-1, -1] == pytest.approx(added, rel=1e-13)
    M[-1, -1] = M0[-1, -1]
    np.testing.assert_array_equal(M, M0)                              # nothing else changes


def test_existing_point_masses_stay():
    chain = plbar.Case(**CHAIN, end_mass=0.1).bar()
    assert chain.paper_chain and chain.point_masses == ((5.0, 1.0), (5.0, 1.0))   # its m/2, then the end mass
    fe = plbar.Case(**FE, n=6, point_masses=((1.5, 0.2),), end_mass=0.5).bar()
    assert fe.point_masses == ((1.5, 0.2), (3.0, 3.0))
    assert plbar.Case(**FE).bar().point_masses == ()                  # 0: none


@pytest.mark.parametrize("value", [-1.0, -1e-300, float("nan"), float("inf"), "0.5", None])
def test_invalid_end_mass(value):
    with pytest.raises(InputError, match=r"end_mass = .*(>= 0|not a number)") as exc:
        plbar.Case(end_mass=value)
    assert "\n" not in str(exc.value) and "end_mass_absolute" in str(exc.value)


@pytest.mark.parametrize("value", [1, "yes", None])
def test_invalid_end_mass_absolute(value):
    with pytest.raises(InputError, match="end_mass_absolute = .* must be True or False"):
        plbar.Case(end_mass=0.5, end_mass_absolute=value)


def test_to_dict_has_both_and_reads_back():
    case = plbar.Case(**FE, n=8, end_mass=0.4, end_mass_absolute=True)
    d = case.to_dict()
    assert d["end_mass"] == 0.4 and d["end_mass_absolute"] is True
    assert plbar.Case(**d) == case
    assert plbar.Case(**FE).to_dict()["end_mass"] == 0.0
    assert case != plbar.Case(**FE, n=8, end_mass=0.4)


@pytest.mark.parametrize("kw", [dict(CHAIN, end_mass=0.1), dict(FE, end_mass=0.25),
                                dict(FE, end_mass=0.7, end_mass_absolute=True), dict(FE)])
def test_toml_round_trip(kw):
    case = plbar.Case(**kw)
    text = dump_case(case)
    assert loads_case(text)[0] == case
    assert ("end_mass" in text) == (case.end_mass != 0 or case.end_mass_absolute)


GOOD = """
[bar]
model = "{model}"
n = 6
{extra}

[[load]]
node = 2
"""


@pytest.mark.parametrize("model", ["chain", "fe"])
def test_toml_end_mass_both_models(model):
    case = loads_case(GOOD.format(model=model, extra="end_mass = 0.5"))[0]
    assert case.end_mass == 0.5 and not case.end_mass_absolute
    case = loads_case(GOOD.format(model=model, extra="end_mass = 2\nend_mass_absolute = true"))[0]
    assert case.end_mass_value == 2.0 and case.end_mass_absolute


@pytest.mark.parametrize("extra,words", [
    ('end_mass = "big"', ["[bar] end_mass", "wrong type", "number"]),
    ("end_mass = true", ["[bar] end_mass", "wrong type", "number"]),
    ("end_mass_absolute = 1", ["[bar] end_mass_absolute", "wrong type", "true or false"]),
    ("end_mass = -1", ["end_mass = -1.0", "must be finite and >= 0"]),
    ("end_mass = inf", ["[bar] end_mass", "finite"]),
])
def test_toml_wrong_end_mass_one_line(extra, words):
    with pytest.raises(CaseFileError) as exc:
        loads_case(GOOD.format(model="fe", extra=extra), "c.toml")
    msg = str(exc.value)
    assert msg.startswith("c.toml: ") and "\n" not in msg
    for w in words:
        assert w in msg
