"""The particle arrays: zero-copy views where the storage cannot move, read-only where the user
must not write, and the documented rules for writing positions, velocities and spins."""

import numpy as np
import pytest

import tsubu


def free_spot_on_floor(sim, i):
    """A place for grain i on the floor, overlapping it by 1 % of its radius, clear of the others."""
    others = np.delete(sim.positions, i, axis=0)
    reach = np.delete(sim.radii, i) + sim.radii[i] + 1e-4
    for x in np.linspace(0, 0.006, 13, endpoint=False):
        for y in np.linspace(0, 0.006, 13, endpoint=False):
            spot = np.array([x, y, 0.99 * sim.radii[i]])
            d = others - spot
            d[:, :2] -= 0.006 * np.round(d[:, :2] / 0.006)  # periodic in x and y
            if (np.linalg.norm(d, axis=1) > reach).all():
                return spot
    raise AssertionError("no free spot on the floor")


def test_arrays_have_the_particle_shapes(bed):
    sim = tsubu.Simulation(bed)
    n = sim.particle_count
    assert n > 50
    for name in ("positions", "velocities", "spins", "forces", "torques"):
        a = getattr(sim, name)
        assert a.shape == (n, 3) and a.dtype == np.float64, name
    for name, dtype in (("ids", np.int64), ("radii", np.float64), ("masses", np.float64), ("contact_counts", np.int32)):
        a = getattr(sim, name)
        assert a.shape == (n,) and a.dtype == dtype, name
    assert sorted(sim.ids.tolist()) == list(range(n))
    assert np.allclose(sim.masses, 2500 * 4 / 3 * np.pi * sim.radii**3, rtol=1e-14)


def test_views_follow_the_run_across_steps_and_sorts(bed):
    sim = tsubu.Simulation(bed)
    positions, ids, forces = sim.positions, sim.ids, sim.forces
    assert np.shares_memory(positions, sim.positions)  # a view, not a copy
    sim.step(120)  # two spatial sorts (every 50 steps) renumber the particles in place
    assert np.array_equal(positions, sim.positions)
    assert np.array_equal(ids, sim.ids)
    assert np.array_equal(forces, sim.forces)
    assert sorted(ids.tolist()) == list(range(sim.particle_count))
    del sim  # the arrays keep the simulation alive
    assert np.isfinite(positions).all()


def test_read_only_arrays_refuse_writes(bed):
    sim = tsubu.Simulation(bed)
    for name in ("ids", "forces", "torques", "radii", "masses", "contact_counts"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(sim, name)[0] = 1
        with pytest.raises(AttributeError):
            setattr(sim, name, getattr(sim, name))


def test_written_velocities_and_positions_take_effect_at_the_next_step(bed):
    sim = tsubu.Simulation(bed)
    top = int(np.argmax(sim.positions[:, 2]))  # a grain touching nothing yet
    assert sim.contact_counts[top] == 0
    x0 = sim.positions[top].copy()
    sim.velocities[top] = [0.2, -0.1, 0.0]
    sim.spins[top] = [0.0, 0.0, 50.0]
    sim.step()
    dt, g = sim.dt, np.array([0.3, 0.1, -9.81])
    # Velocity Verlet on a free grain: x1 = x0 + v dt + g dt^2 / 2 (here wrapped into the box).
    assert np.allclose(sim.positions[top], x0 + np.array([0.2, -0.1, 0.0]) * dt + 0.5 * g * dt * dt, rtol=0, atol=1e-15)
    assert sim.spins[top].tolist() == [0.0, 0.0, 50.0]
    # Moving a grain far (more than half the skin) rebuilds the neighbour lists: it lands on
    # the floor, touches it at the next evaluation and is pushed up.
    sim.positions[top] = free_spot_on_floor(sim, top)
    sim.velocities[top] = 0
    sim.step()
    walls = sim.wall_contacts()
    assert top in walls["i"].tolist()
    assert sim.forces[top][2] > 0


def test_assigning_whole_arrays_copies_them_in(bed):
    sim = tsubu.Simulation(bed)
    v = np.zeros((sim.particle_count, 3))
    sim.velocities = v
    assert not sim.velocities.any()
    with pytest.raises(ValueError, match=r"shape \(\d+, 3\)"):
        sim.velocities = np.zeros((3, 3))


def test_block_hermite_runs_refuse_writes(block_bed):
    sim = tsubu.Simulation(block_bed)
    assert not sim.state_writable
    for name in ("positions", "velocities", "spins"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(sim, name)[0, 0] = 0.001
        with pytest.raises(RuntimeError, match="block_hermite"):
            setattr(sim, name, getattr(sim, name).copy())


def test_runs_with_an_inflow_give_read_only_copies(inflow_scenario):
    sim = tsubu.Simulation(inflow_scenario)
    before = sim.particle_count
    positions = sim.positions
    sim.advance_to(0.05)
    assert sim.particle_count > before  # grains entered: the storage may have moved
    assert positions.shape[0] == before and not np.shares_memory(positions, sim.positions)
    with pytest.raises(ValueError, match="read-only"):
        sim.positions[0, 0] = 0
    sim.velocities = np.zeros((sim.particle_count, 3))  # assignment still works
    assert not sim.velocities.any()
