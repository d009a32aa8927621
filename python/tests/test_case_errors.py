"""A case from a dict is checked by the case loader itself: the same errors as a file's, with
the key path in place of the line."""
import pytest

import ckpd


def test_an_unknown_key_in_a_dict_raises_case_error_naming_its_key_path(plate):
    plate["bodies"][0]["spacng"] = 0.05
    with pytest.raises(ckpd.CaseError, match=r"^case dict: bodies\[0\]\.spacng: unknown key 'spacng'"):
        ckpd.Simulation(plate)


def test_a_bad_value_in_a_dict_names_its_key_path_and_what_was_expected(plate):
    plate["conditions"][1]["value"] = [0, "fast"]
    with pytest.raises(ckpd.CaseError, match=r"case dict: conditions\[1\]\.value\[1\]: expected a number"):
        ckpd.Simulation(plate)


def test_a_value_python_cannot_spell_in_yaml_is_refused_with_its_path(plate):
    plate["bodies"][0]["spacing"] = object()
    with pytest.raises(ckpd.CaseError, match=r"case dict: bodies\[0\]\.spacing: expected a dict, list"):
        ckpd.Simulation(plate)


def test_case_error_is_a_value_error():
    assert issubclass(ckpd.CaseError, ValueError)
    assert issubclass(ckpd.SweepError, ckpd.CaseError)
    assert issubclass(ckpd.TunnellingError, ckpd.InstabilityError)


def test_a_file_case_error_names_file_and_line(tmp_path, plate):
    import yaml

    plate["time"]["stpes"] = 3
    file = tmp_path / "bad.yaml"
    file.write_text(yaml.safe_dump(plate, sort_keys=False))
    with pytest.raises(ckpd.CaseError, match=r"bad\.yaml:\d+: time\.stpes: unknown key"):
        ckpd.Simulation(str(file))


def test_overrides_are_those_of_set(plate):
    sim = ckpd.Simulation(plate, overrides={"bodies.plate.spacing": 0.1, "time.steps": 2})
    assert sim.bodies["plate"].size == 100 and sim.planned_steps == 2
    sim = ckpd.Simulation(plate, overrides=["time.steps=7"])
    assert sim.planned_steps == 7
    with pytest.raises(ckpd.CaseError, match=r"--set bodies\.slab\.spacing: 'bodies' has no element 'slab'"):
        ckpd.Simulation(plate, overrides={"bodies.slab.spacing": 0.1})


def test_check_case_accepts_a_good_case_and_rejects_a_bad_one(plate):
    ckpd.check_case(plate)
    plate["materials"]["steel"]["density"] = -1
    with pytest.raises(ckpd.CaseError, match=r"materials\.steel\.density"):
        ckpd.check_case(plate)
