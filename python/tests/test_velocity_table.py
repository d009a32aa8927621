"""The `velocity_table` condition (a `velocity` whose table is written as two lists): the grip
moves by the integral of its table (the drift uses the midpoint velocity, exact for a linear
piece), it is the `value: {table}` form bit for bit, and bad tables are refused with their
path."""
import copy

import numpy as np
import pytest

import ckpd


def with_table(plate, **table):
    plate["conditions"][0] = {"type": "velocity_table", "body": "plate",
                              "region": plate["conditions"][0]["region"], "components": ["y"],
                              **table}
    return plate


def grip_displacement(sim):
    return sim.bodies["plate"].displacements[sim.conditions[0].points, 1]


def test_a_linear_table_moves_the_grip_by_its_integral(plate):
    dt = plate["time"]["dt"]
    # 0 -> 4 m/s over 20 steps, then down to 1 m/s at step 50, held to step 60.
    sim = ckpd.Simulation(with_table(plate, times=[0, 20 * dt, 50 * dt], values=[[0, 0], [0, 4], [0, 1]]))
    sim.run()
    exact = (0.5 * 4 * 20 + 0.5 * (4 + 1) * 30 + 1 * 10) * dt
    assert grip_displacement(sim) == pytest.approx(exact, rel=1e-12)
    assert sim.bodies["plate"].velocities[sim.conditions[0].points, 1] == pytest.approx(1.0, rel=1e-12)


def test_a_step_table_holds_each_value_until_the_next_time(plate):
    dt = plate["time"]["dt"]
    sim = ckpd.Simulation(with_table(plate, times=[0, 10.25 * dt], values=[[0, 2], [0, -3]],
                                     interpolation="step"))
    sim.run()
    assert grip_displacement(sim) == pytest.approx((2 * 10 - 3 * 50) * dt, rel=1e-12)


@pytest.mark.parametrize("interpolation", ["linear", "step"])
def test_the_two_lists_are_the_velocity_table_form_bit_for_bit(plate, interpolation):
    dt = plate["time"]["dt"]
    times, values = [0, 20.5 * dt, 50.5 * dt], [[0, 0], [0, 4], [0, 1]]
    lists = ckpd.Simulation(with_table(copy.deepcopy(plate), times=times, values=values,
                                       interpolation=interpolation))
    table = copy.deepcopy(plate)
    table["conditions"][0] = {"type": "velocity", "body": "plate",
                              "region": plate["conditions"][0]["region"], "components": ["y"],
                              "value": {"table": [[t] + v for t, v in zip(times, values)],
                                        "interpolation": interpolation}}
    form = ckpd.Simulation(table)
    lists.run()
    form.run()
    assert np.array_equal(lists.bodies["plate"].displacements, form.bodies["plate"].displacements)
    assert np.array_equal(lists.bodies["plate"].velocities, form.bodies["plate"].velocities)


@pytest.mark.parametrize("table, message", [
    ({"times": [0, 1e-4, 1e-4], "values": [[0, 1]] * 3}, r"conditions\[0\]\.times\[2\]: expected a time above the one before it"),
    ({"times": [0, 1e-4], "values": [[0, 1]]}, r"conditions\[0\]\.values: expected one value per time \(2\)"),
    ({"times": [0], "values": [[0, 1]], "interpolation": "cubic"}, r"conditions\[0\]\.interpolation: expected linear or step"),
    ({"times": [-1e-4], "values": [[0, 1]]}, r"conditions\[0\]\.times\[0\]"),
])
def test_bad_tables_are_refused_with_their_key_path(plate, table, message):
    with pytest.raises(ckpd.CaseError, match=message):
        ckpd.Simulation(with_table(plate, **table))
