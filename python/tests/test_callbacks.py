"""Callbacks run between steps; one that raises stops the run cleanly."""
import traceback

import numpy as np
import pytest

import ckpd


class Boom(Exception):
    pass


def exploding_callback(sim):
    if sim.step_number == 30:
        raise Boom("controller failed")


def test_a_callback_that_raises_stops_the_run_with_its_traceback_and_keeps_the_history(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=str(tmp_path / "run"))
    with pytest.raises(Boom, match="controller failed") as info:
        sim.run(callback=exploding_callback, every=5)
    frames = [f.name for f in traceback.extract_tb(info.tb)]
    assert "exploding_callback" in frames  # the Python traceback came through
    assert sim.step_number == 30 and sim.status == "failed"
    run = ckpd.open_run(tmp_path / "run")
    assert list(run.history["step"]) == [0, 10, 20, 30]
    assert run.summary["status"] == "failed"
    assert "Boom" in run.summary["message"] and "step 30" in run.summary["message"]
    # The run has ended with its summary: no step after it.
    with pytest.raises(RuntimeError, match=r"the run has ended \(status 'failed' at step 30\)"):
        sim.run()
    assert len(ckpd.open_run(tmp_path / "run").history["step"]) == 4


def test_a_callback_returning_false_stops_the_run(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=str(tmp_path / "run"))
    seen = []

    def until_step_20(s):
        seen.append(s.step_number)
        return s.step_number < 20

    assert sim.run(callback=until_step_20, every=4) == 20
    assert seen == [4, 8, 12, 16, 20]
    run = ckpd.open_run(tmp_path / "run")
    assert run.summary["status"] == "stopped" and run.history["step"][-1] == 20


def test_run_by_steps_and_until_and_past_the_end(plate):
    sim = ckpd.Simulation(plate)
    assert sim.run(steps=7) == 7
    sim.run(until=20 * sim.dt)
    assert sim.step_number == 20 and sim.time == pytest.approx(20 * sim.dt)
    with pytest.raises(ValueError, match="the case ends at step 60"):
        sim.run(steps=100)
    sim.run()
    assert sim.step_number == 60 and sim.status == "completed"


def test_energies_after_a_run_are_current(plate):
    sim = ckpd.Simulation(plate)
    sim.run(steps=13)  # not a history step: the last step still evaluates the energy
    e = sim.energies
    strain = float(np.sum(sim.bodies["plate"].strain_energy_density * sim.bodies["plate"].volumes))
    assert e["strain"] == pytest.approx(strain, rel=1e-12) and e["strain"] > 0
