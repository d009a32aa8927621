"""Sweeps from Python: a sweep file through the sweep runner, or a list of cases in-process."""
import yaml

import ckpd


def test_a_list_of_dict_cases_gives_a_table_with_the_metrics(tmp_path, plate):
    coarse = dict(plate, bodies=[dict(plate["bodies"][0], spacing=0.1)])
    bad = dict(plate, time={"steps": 5, "dt": -1})
    table = ckpd.run_cases([plate, coarse, bad], tmp_path,
                           metrics={"points": "bodies.plate.points", "work": "energy.external_work"})
    assert len(table) == 3
    assert list(table["status"]) == ["completed", "completed", "failed"]
    assert list(table["points"][:2]) == [400, 100]
    assert table["work"][0] > 0
    assert "time.dt" in table.rows[2]["message"]
    assert ckpd.open_run(tmp_path / "0001").summary["bodies"][0]["points"] == 100
    assert (tmp_path / "cases.csv").exists()


def test_a_sweep_file_runs_and_returns_its_table(tmp_path, plate):
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(plate, sort_keys=False))
    (tmp_path / "sweep.yaml").write_text(
        "base: base.yaml\n"
        "set:\n  time.steps: 10\n"
        "parameters:\n  dx: {key: bodies.plate.spacing, values: [0.1, 0.05]}\n"
        "metrics:\n  points: bodies.plate.points\n")
    table = ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "out", jobs=1, threads_per_run=1)
    assert table.exit_status == 0 and table.completed
    assert list(table["dx"]) == [0.1, 0.05]
    assert list(table["points"]) == [100, 400]


def test_a_bad_sweep_file_raises_sweep_error(tmp_path):
    (tmp_path / "sweep.yaml").write_text("base: missing.yaml\nparameters: {}\n")
    try:
        ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "out")
    except ckpd.CaseError as e:  # SweepError is a CaseError
        assert "missing.yaml" in str(e)
    else:
        raise AssertionError("no error")
