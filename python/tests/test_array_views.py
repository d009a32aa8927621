"""Body state reaches numpy without copies: the arrays are views of the engine's own vectors."""
import numpy as np
import pytest

import ckpd


def data_pointer(a):
    return a.__array_interface__["data"][0]


def test_state_arrays_are_views_that_a_step_changes_in_place(plate):
    sim = ckpd.Simulation(plate)
    body = sim.bodies["plate"]
    u, v, f = body.displacements, body.velocities, body.force_density
    before = (u.copy(), v.copy(), f.copy())
    sim.run(steps=3)
    assert sim.step_number == 3
    # The arrays taken before the steps now hold the new state...
    assert not np.array_equal(u, before[0])
    assert not np.array_equal(v, before[1])
    assert not np.array_equal(f, before[2])
    # ...because they are the same memory as what the engine exposes now.
    for old, new in ((u, body.displacements), (v, body.velocities), (f, body.force_density)):
        assert data_pointer(old) == data_pointer(new)
        assert np.array_equal(old, new)
    assert u.shape == (400, 2) and body.volumes.shape == (400,)
    assert not u.flags.owndata and not body.volumes.flags.owndata


def test_views_keep_the_simulation_alive(plate):
    u = ckpd.Simulation(plate).bodies["plate"].reference_positions
    import gc

    gc.collect()
    assert u.min() == pytest.approx(0.025) and u.max() == pytest.approx(0.975)


@pytest.mark.parametrize("name", ["displacements", "reference_positions", "accelerations",
                                  "force_density", "volumes", "strain_energy_density",
                                  "positions", "damage"])
def test_writing_a_read_only_array_raises(plate, name):
    a = getattr(ckpd.Simulation(plate).bodies["plate"], name)
    with pytest.raises(ValueError, match="read-only"):
        a[0] = 1.0


def test_written_velocities_steer_the_next_step(plate):
    plate["conditions"] = []
    sim = ckpd.Simulation(plate)
    body = sim.bodies["plate"]
    body.velocities[:, 0] = 2.0  # the whole plate moves in x: no strain
    sim.step()
    assert np.allclose(body.displacements[:, 0], 2.0 * sim.dt, rtol=1e-9)
    kinetic = 0.5 * 7580 * 4.0 * body.volumes.sum()
    assert sim.energies["kinetic"] == pytest.approx(kinetic, rel=1e-9)
    # The energy written in is booked as external work: the balance still closes.
    assert sim.energies["external_work"] == pytest.approx(kinetic, rel=1e-9)
    assert abs(sim.energies["balance_error"]) < 1e-9 * kinetic


def test_positions_are_reference_plus_displacement(plate):
    sim = ckpd.Simulation(plate)
    sim.run(steps=5)
    b = sim.bodies["plate"]
    assert np.array_equal(b.positions, b.reference_positions + b.displacements)
