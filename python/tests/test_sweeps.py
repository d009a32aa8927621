"""Sweeps from Python: a sweep file through the sweep runner, or a list of cases in-process; the
table's rows typed (numbers as numbers), progress printed only on request."""
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


def test_rows_hold_typed_cells_and_read_back_the_same(tmp_path, plate):
    bad = dict(plate, time={"steps": 5, "dt": -1})
    table = ckpd.run_cases([plate, bad], tmp_path, metrics={"points": "bodies.plate.points",
                                                           "work": "energy.external_work"})
    good, failed = table.rows
    assert good["index"] == 0 and good["points"] == 400 and isinstance(good["points"], int)
    assert isinstance(good["work"], float) and isinstance(good["wall_seconds"], float)
    assert good["status"] == "completed" and good["message"] == ""
    assert failed["index"] == 1 and failed["points"] is None and failed["status"] == "failed"
    assert table["points"].dtype.kind == "f"  # a missing cell makes the column float (nan)
    assert table["index"].dtype.kind == "i"
    again = ckpd.SweepTable.read(tmp_path / "cases.csv")
    assert again.rows == table.rows and again.header == table.header


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
    assert [r["points"] for r in table.rows] == [100, 400]
    assert [type(r["dx"]) for r in table.rows] == [float, float]


def test_progress_is_printed_only_on_request(tmp_path, plate, capfd):
    plate["time"]["steps"] = 2
    ckpd.run_cases([plate], tmp_path / "quiet")
    assert capfd.readouterr().out == ""
    ckpd.run_cases([plate], tmp_path / "loud", progress=True)
    out = capfd.readouterr().out
    assert "case 0: completed in" in out
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(plate, sort_keys=False))
    (tmp_path / "sweep.yaml").write_text(
        "base: base.yaml\nparameters:\n  dx: {key: bodies.plate.spacing, values: [0.1]}\n")
    ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "s1", jobs=1, threads_per_run=1)
    assert "".join(capfd.readouterr()) == ""
    ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "s2", jobs=1, threads_per_run=1,
                   progress=True)
    assert "".join(capfd.readouterr()) != ""


def test_a_bad_sweep_file_raises_sweep_error(tmp_path):
    (tmp_path / "sweep.yaml").write_text("base: missing.yaml\nparameters: {}\n")
    try:
        ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "out")
    except ckpd.CaseError as e:  # SweepError is a CaseError
        assert "missing.yaml" in str(e)
    else:
        raise AssertionError("no error")
