"""A prescribed velocity changed between steps from Python runs as the case-file `velocity`
with a step table (`value: {table: ..., interpolation: step}`) that makes that change at the
same time: the same state bit for bit."""
import numpy as np
import pytest

import ckpd

SWITCH_STEP = 20


def table(value_before, value_after, switch_time, region):
    return {"type": "velocity", "body": "plate", "region": region,
            "value": {"table": [[0.0, 0, value_before], [switch_time, 0, value_after]],
                      "interpolation": "step"},
            "components": ["y"]}


def test_steering_a_velocity_between_steps_equals_the_piecewise_velocity_case(plate):
    steered = ckpd.Simulation(plate)
    top, bottom = steered.conditions
    assert (top.type, top.body) == ("velocity", "plate")
    assert np.array_equal(top.value, [0, 5.0])

    def controller(sim):
        if sim.step_number == SWITCH_STEP:  # slow the grips down to 1 m/s
            top.value = [0, 1.0]
            bottom.value = [0, -1.0]

    steered.run(callback=controller)

    # The change takes effect in the step after SWITCH_STEP: the velocity at the end of that
    # step is still the old one, the next midpoint's the new one. A switch a quarter step after
    # it lies between the two, clear of rounding.
    reference = dict(plate)
    switch = (SWITCH_STEP + 0.25) * steered.dt
    reference["conditions"] = [
        table(5.0, 1.0, switch, plate["conditions"][0]["region"]),
        table(-5.0, -1.0, switch, plate["conditions"][1]["region"]),
    ]
    ref = ckpd.Simulation(reference)
    assert ref.dt == steered.dt
    ref.run()

    a, b = steered.bodies["plate"], ref.bodies["plate"]
    assert np.array_equal(a.displacements, b.displacements)
    assert np.array_equal(a.velocities, b.velocities)
    assert steered.energies == ref.energies
    # Not a test of nothing: without the change the run ends elsewhere.
    unsteered = ckpd.Simulation(plate)
    unsteered.run()
    assert not np.array_equal(unsteered.bodies["plate"].displacements, a.displacements)
    # The grips moved 5 m/s for 20.5 steps (velocity at the midpoints), 1 m/s after.
    grip = a.displacements[top.points, 1]
    assert grip == pytest.approx((5.0 * (SWITCH_STEP) + 1.0 * (60 - SWITCH_STEP)) * steered.dt, rel=1e-12)


def test_a_condition_without_a_value_refuses_a_new_one(plate):
    plate["conditions"][1]["type"] = "fixed"
    del plate["conditions"][1]["value"]
    sim = ckpd.Simulation(plate)
    assert sim.conditions[1].value is None
    with pytest.raises(ValueError, match="condition 1 \\(fixed on 'plate'\\) has no value"):
        sim.conditions[1].value = [0, 1]
    with pytest.raises(ValueError, match="expected 2 numbers"):
        sim.conditions[0].value = [0, 1, 2]
