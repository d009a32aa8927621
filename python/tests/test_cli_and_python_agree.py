"""The same case run by `ckpd run` and by ckpd.Simulation writes the same results, bit for bit:
both step through the same RunDriver."""
import json
import os
import subprocess

import numpy as np
import yaml

import ckpd
from ckpd._program import PROGRAM

OVERRIDES = {
    "bodies.plate.spacing": 0.05,
    "conditions.0.region.min": [0, 0.85],
    "conditions.1.region.max": [1, 0.15],
    "conditions.0.value": [0, 5.0],
    "conditions.1.value": [0, -5.0],
    "time.end": 3e-4,
    "output.history_interval": 10,
    "output.field_interval": 20,
    "output.fields": ["position", "displacement", "velocity", "damage", "force_density"],
}


def sets(overrides):
    return [f"{k}={json.dumps(v)}" for k, v in overrides.items()]


def test_cli_and_python_give_bit_identical_summary_energies_history_and_final_fields(tmp_path, source_dir):
    case = str(source_dir / "cases" / "mode1_2d.yaml")
    cli, py = tmp_path / "cli", tmp_path / "py"
    args = [PROGRAM, "run", case, "--out", str(cli), "--threads", "1", "--quiet"]
    for s in sets(OVERRIDES):
        args += ["--set", s]
    subprocess.run(args, check=True)
    sim = ckpd.Simulation(case, overrides=OVERRIDES, out=str(py), threads=1)
    sim.run()
    assert sim.status == "completed"

    a, b = ckpd.open_run(cli), ckpd.open_run(py)
    assert a.summary["status"] == b.summary["status"] == "completed"
    assert a.summary["energy"] == b.summary["energy"]
    assert a.summary["energy"]["dissipated"] > 0  # the crack ran: a test with something in it
    assert a.summary["bodies"][0]["broken_bonds"] == b.summary["bodies"][0]["broken_bonds"] > 0
    assert (cli / "history.csv").read_text() == (py / "history.csv").read_text()
    assert len(a.frame_files) == len(b.frame_files) > 1
    for name in ("position", "displacement", "velocity", "damage", "force_density"):
        assert np.array_equal(a.field("plate", name)[-1], b.field("plate", name)[-1]), name
    # And the live state is what was written last.
    assert np.array_equal(b.field("plate", "displacement")[-1][:, :2],
                          sim.bodies["plate"].displacements)


def test_a_dict_case_runs_as_its_file(tmp_path, source_dir):
    file = source_dir / "cases" / "mode1_2d.yaml"
    overrides = {"bodies.plate.spacing": 0.05, "time.end": 1e-4,
                 "conditions.0.region.min": [0, 0.85], "conditions.1.region.max": [1, 0.15]}
    from_file = ckpd.Simulation(str(file), overrides=overrides, threads=1)
    from_dict = ckpd.Simulation(yaml.safe_load(file.read_text()), overrides=overrides, threads=1)
    from_file.run()
    from_dict.run()
    assert from_file.energies == from_dict.energies
    assert np.array_equal(from_file.bodies["plate"].displacements,
                          from_dict.bodies["plate"].displacements)
