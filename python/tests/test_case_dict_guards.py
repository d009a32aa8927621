"""A case dict is converted with cycle and depth checks: a dict that contains itself, a value
nested deeper than a case ever is, and a numpy-like object whose tolist() returns itself raise
CaseError naming the key path (they used to crash the interpreter in the conversion)."""
import pytest

import ckpd

BASE = {"materials": {}, "bodies": [], "time": {"steps": 1}}


def test_a_dict_that_contains_itself_raises_case_error_naming_the_cycle():
    case = dict(BASE)
    case["description"] = case
    with pytest.raises(ckpd.CaseError, match=r"^case dict: description: the value of \(top level\) again, which contains it \(a cycle"):
        ckpd.check_case(case)


def test_a_list_that_contains_itself_further_down_raises_case_error():
    loop = [1, 2]
    loop.append({"again": loop})
    with pytest.raises(ckpd.CaseError, match=r"case dict: description\[2\]\.again: the value of description again"):
        ckpd.check_case(dict(BASE, description=loop))


def test_nesting_a_hundred_thousand_levels_deep_raises_case_error():
    x = 1
    for _ in range(100_000):
        x = [x]
    with pytest.raises(ckpd.CaseError, match=r"nested deeper than 500 levels"):
        ckpd.check_case(dict(BASE, description=x))


def test_an_object_whose_tolist_returns_itself_raises_case_error():
    class SelfList:
        dtype = "float64"

        def tolist(self):
            return self

    with pytest.raises(ckpd.CaseError, match=r"case dict: description: the value of description again"):
        ckpd.check_case(dict(BASE, description=SelfList()))


def test_the_same_list_in_two_places_is_no_cycle(plate):
    corner = [0, 0]
    plate["bodies"][0]["geometry"]["min"] = corner
    plate["conditions"][1]["region"]["min"] = corner
    assert ckpd.Simulation(plate).bodies["plate"].size == 400


def test_an_override_that_contains_itself_raises_case_error(plate):
    value = [0.0]
    value.append(value)
    with pytest.raises(ckpd.CaseError, match=r"case dict: bodies\.plate\.spacing\[1\]: the value of bodies\.plate\.spacing again"):
        ckpd.Simulation(plate, overrides={"bodies.plate.spacing": value})
