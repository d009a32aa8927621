"""One call at a time per Simulation: while run() computes (without the GIL) in one thread, a
call from another thread raises BusyError instead of stepping the same state (steps used to
vanish); the run's own callback may still read, steer and write checkpoints."""
import threading
import time

import pytest

import ckpd


def _running(plate, steps=300):
    """A simulation and a thread running it; returns once the run has made its first step."""
    plate["bodies"][0]["spacing"] = 0.02  # 2500 points
    plate["time"] = {"steps": 4000, "dt": 2e-6}
    sim = ckpd.Simulation(plate, threads=1)
    started = threading.Event()

    def first_step(s):
        started.set()
        return True

    thread = threading.Thread(target=lambda: sim.run(steps=steps, callback=first_step, every=1))
    thread.start()
    assert started.wait(60)
    return sim, thread


def test_a_second_thread_cannot_step_while_run_computes(plate):
    sim, thread = _running(plate)
    refused = stepped = 0
    while thread.is_alive():
        try:
            sim.step()  # succeeds only once the run has returned
            stepped += 1
        except ckpd.BusyError as e:
            assert "Simulation.step: the simulation is busy: Simulation.run is running in another thread" in str(e)
            refused += 1
        time.sleep(0.0005)
    thread.join()
    assert refused > 0
    assert sim.step_number == 300 + stepped  # no step lost or doubled


@pytest.mark.parametrize("call", [lambda s: s.run(steps=1), lambda s: s.finish(),
                                  lambda s: s.checkpoint("never.h5"), lambda s: s.energies,
                                  lambda s: s.bodies["plate"], lambda s: s.conditions[0].value])
def test_every_call_from_another_thread_is_refused_while_run_computes(plate, call):
    sim, thread = _running(plate, steps=400)
    with pytest.raises(ckpd.BusyError, match="the simulation is busy"):
        call(sim)
    thread.join()
    assert sim.step_number == 400 and sim.status == "running"


def test_status_and_repr_answer_from_another_thread(plate):
    sim, thread = _running(plate)
    assert sim.status == "running"
    assert repr(sim).endswith("busy in another thread>")
    thread.join()


def test_the_callback_may_read_and_steer_but_not_step(plate):
    sim = ckpd.Simulation(plate)
    grip = sim.conditions[0]
    seen = []

    def callback(s):
        seen.append((s.step_number, s.energies["kinetic"]))
        grip.value = [0, 6.0]
        with pytest.raises(RuntimeError, match=r"Simulation.step: called from inside Simulation.run \(a callback\)"):
            s.step()
        return True

    sim.run(steps=20, callback=callback, every=10)
    assert [n for n, _ in seen] == [10, 20] and list(grip.value) == [0, 6.0]
    sim.run(steps=1)  # free again once run() has returned
    assert sim.step_number == 21
