"""ckpd.open_run reads a run folder into numpy: history, summary, field frames."""
import numpy as np
import pytest

import ckpd


def test_open_run_reads_history_summary_and_frames(tmp_path, plate):
    plate["output"].update({"field_interval": 15, "fields": ["displacement", "damage"]})
    sim = ckpd.Simulation(plate, out=str(tmp_path))
    sim.run()
    run = ckpd.open_run(tmp_path)
    assert list(run.history["step"]) == [0, 10, 20, 30, 40, 50, 60]
    assert run.history["time"][-1] == pytest.approx(sim.time, rel=1e-9)
    assert run.history["kinetic"][-1] == pytest.approx(sim.energies["kinetic"], rel=1e-9)
    assert run.summary["status"] == "completed" and run.summary["steps"] == 60
    assert run.bodies == ["plate"]
    assert list(run.steps) == [0, 15, 30, 45, 60]
    assert np.allclose(run.times, run.steps * sim.dt, rtol=1e-12)
    u = run.field("plate", "displacement")
    assert u.shape == (5, 400, 3)
    assert np.array_equal(u[-1][:, :2], sim.bodies["plate"].displacements)
    assert np.array_equal(run.field("plate", "damage")[-1].ravel(), sim.bodies["plate"].damage)
    assert set(run.frame(0)["plate"]) >= {"position", "displacement", "damage"}
    with pytest.raises(KeyError, match="no field 'velocity'"):
        run.field("plate", "velocity")


def test_checkpoint_and_restart_continue_bit_for_bit(tmp_path, plate):
    whole = ckpd.Simulation(plate)
    whole.run()
    first = ckpd.Simulation(plate)
    first.run(steps=25)
    path = first.checkpoint(str(tmp_path / "c.h5"))
    second = ckpd.Simulation(plate, restart=path)
    assert second.step_number == 25
    second.run()
    assert np.array_equal(second.bodies["plate"].displacements, whole.bodies["plate"].displacements)
    assert second.energies == whole.energies
    assert second.broken_bonds == whole.broken_bonds


def test_a_checkpoint_of_other_physics_is_refused(tmp_path, plate):
    sim = ckpd.Simulation(plate)
    sim.run(steps=2)
    path = sim.checkpoint(str(tmp_path / "c.h5"))
    plate["bodies"][0]["spacing"] = 0.1
    with pytest.raises(ckpd.CheckpointError):
        ckpd.Simulation(plate, restart=path)
