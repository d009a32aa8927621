"""finish() ends a run for good and takes only a status the run can justify: no step after it
(history.csv used to grow past the summary), 'completed' only at the last planned step (it was
written at step 6 of 60)."""
import json

import pytest

import ckpd


def _history_rows(folder):
    return len((folder / "history.csv").read_text().splitlines()) - 1


def test_no_step_after_finish(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=tmp_path, threads=1)
    sim.run(steps=5)
    sim.finish()
    rows = _history_rows(tmp_path)
    with pytest.raises(RuntimeError, match=r"the run has ended \(status 'stopped' at step 5\)"):
        sim.step()
    with pytest.raises(RuntimeError, match=r"the run has ended"):
        sim.run()
    assert sim.step_number == 5 and _history_rows(tmp_path) == rows
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "stopped" and summary["steps"] == 5


def test_completed_before_the_last_step_is_refused(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=tmp_path, threads=1)
    sim.run(steps=6)
    with pytest.raises(ValueError, match=r"status 'completed' needs the run at its last step \(60\); it is at step 6"):
        sim.finish("completed")
    assert not (tmp_path / "summary.json").exists() and sim.status == "running"
    sim.finish("failed", "the grip slipped")
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert (summary["status"], summary["message"]) == ("failed", "the grip slipped")


@pytest.mark.parametrize("status", ["unstable", "tunnelling", "interrupted", "running", "done"])
def test_statuses_only_the_run_sets_are_refused(plate, status):
    sim = ckpd.Simulation(plate)
    with pytest.raises(ValueError, match=rf"status '{status}': expected 'stopped' or 'failed'"):
        sim.finish(status)


def test_finish_after_the_end_keeps_the_summary(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=tmp_path, threads=1)
    sim.run()
    assert sim.status == "completed"
    sim.finish()  # nothing to do
    with pytest.raises(RuntimeError, match=r"already ended \(status 'completed' at step 60\)"):
        sim.finish("stopped")
    assert json.loads((tmp_path / "summary.json").read_text())["status"] == "completed"


def test_finish_in_a_callback_ends_the_run_there(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=tmp_path, threads=1)
    done = sim.run(callback=lambda s: s.finish("stopped", "enough") if s.step_number == 30 else True,
                   every=10)
    assert done == 30 and sim.status == "stopped"
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert (summary["status"], summary["message"], summary["steps"]) == ("stopped", "enough", 30)
