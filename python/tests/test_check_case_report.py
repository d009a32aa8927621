"""ckpd.check_case returns the report `ckpd check` prints, as a dict: the same sizes, step and
planned steps as the program's report of the same case."""
import re
import subprocess

import pytest
import yaml

import ckpd
from ckpd.sweep import _program


def test_the_report_holds_what_ckpd_check_prints(tmp_path, plate):
    file = tmp_path / "plate.yaml"
    file.write_text(yaml.safe_dump(plate, sort_keys=False))
    printed = subprocess.run([_program(), "check", str(file), "--threads", "1"],
                             capture_output=True, text=True, check=True).stdout
    report = ckpd.check_case(file, threads=1)
    body = report["bodies"][0]
    m = re.search(r"body 'plate': 2D, (\d+) points, (\d+) bonds, N2 (\d+), N3 (\d+)", printed)
    assert (body["points"], body["bonds"], body["two_neighbour"], body["three_neighbour"]) == tuple(map(int, m.groups()))
    assert body["name"] == "plate" and body["dimension"] == 2 and body["rigid"] is False
    assert body["spacing"] == 0.05 and body["horizon"] == pytest.approx(3.015 * 0.05)
    assert body["mass"] == pytest.approx(7580 * 1.0, rel=1e-12)  # kg per m of thickness
    m = re.search(r"time step: (\S+) s .*?(\d+) steps", printed)
    assert report["time"]["dt"] == float(m.group(1)) == 5e-6
    assert report["time"]["planned_steps"] == int(m.group(2)) == 60
    assert report["time"]["dt_from_case"] is True and report["time"]["step_mode"] == "fixed"
    estimate = float(re.search(r"stable step: estimate (\S+) s", printed).group(1))
    assert report["stable_step"]["estimate"] == pytest.approx(estimate, rel=1e-5)
    assert report["case"] == str(file)
    timing = report["timing"]
    assert timing["timed_steps"] == 3 and timing["threads"] == 1
    assert timing["seconds_per_step"] > 0 and timing["projected_seconds"] > timing["setup_seconds"]
    assert report["memory"]["body_data_mb"] > 0
    printed_warnings = re.findall(r"^warning: (.*)$", printed, flags=re.M)
    assert report["warnings"] == printed_warnings


def test_the_report_lists_the_set_up_warnings(plate):
    # A damage field in a case where no body can break (the plate's material has no Gc here).
    case = dict(plate)
    case["materials"] = {k: {kk: vv for kk, vv in v.items() if kk != "fracture_energy"}
                         for k, v in plate["materials"].items()}
    case["output"] = {"fields": ["damage"], "field_interval": 10}
    report = ckpd.check_case(case, steps=0)
    assert any("no body can break" in w for w in report["warnings"])


def test_no_timed_steps_gives_no_timing(plate):
    report = ckpd.check_case(plate, overrides={"bodies.plate.spacing": 0.1}, steps=0)
    assert report["case"] == "case dict" and report["bodies"][0]["points"] == 100
    assert report["timing"]["timed_steps"] == 0 and report["timing"]["seconds_per_step"] is None
