"""Steps run without the GIL: other Python threads go on while sim.run computes."""
import threading
import time

import ckpd


def test_a_python_thread_keeps_running_while_sim_run_computes(plate):
    plate["bodies"][0]["spacing"] = 0.02  # 2500 points
    plate["time"] = {"steps": 400, "dt": 2e-6}
    sim = ckpd.Simulation(plate, threads=1)
    ticks = []
    running = threading.Event()
    stop = threading.Event()

    def ticker():
        running.set()
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=ticker)
    thread.start()
    running.wait()
    start = time.perf_counter()
    sim.run()
    end = time.perf_counter()
    stop.set()
    thread.join()
    during = [t for t in ticks if start < t < end]
    assert end - start > 0.1, "the run was too short to tell"
    # A thread held off by the GIL would tick at most a few times (at the signal checks).
    assert len(during) > 0.2 * (end - start) / 0.0011
