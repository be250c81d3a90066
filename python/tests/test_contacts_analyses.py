"""The contact list and the measurements on the current state."""

import numpy as np
import pytest

import tsubu


@pytest.fixture
def settled(bed):
    sim = tsubu.Simulation(bed)
    sim.advance_to(0.004)
    return sim


def test_contacts_sum_to_the_particle_forces(settled):
    sim = settled
    pairs, walls = sim.contacts(), sim.wall_contacts()
    assert len(pairs["i"]) >= 10 and len(walls["i"]) >= 5
    assert (pairs["i"] < pairs["j"]).all() and (pairs["overlap"] > 0).all() and (walls["overlap"] > 0).all()
    assert np.array_equal(pairs["id_i"], sim.ids[pairs["i"]]) and np.array_equal(pairs["id_j"], sim.ids[pairs["j"]])
    assert (walls["wall"] == 0).all()
    # Newton's third law and gravity: the contact forces and m g make every particle's force.
    total = sim.masses[:, None] * np.array([0.3, 0.1, -9.81])
    np.add.at(total, pairs["i"], pairs["force"])
    np.add.at(total, pairs["j"], -pairs["force"])
    np.add.at(total, walls["i"], walls["force"])
    assert np.allclose(total, sim.forces, rtol=0, atol=1e-9 * np.abs(sim.forces).max())
    counts = np.bincount(np.concatenate([pairs["i"], pairs["j"], walls["i"]]), minlength=sim.particle_count)
    assert np.array_equal(counts, sim.contact_counts)


def test_energies_are_the_series_columns(settled):
    e = settled.energies()
    v, w, m, r = settled.velocities, settled.spins, settled.masses, settled.radii
    assert e["kinetic_translational"] == pytest.approx(0.5 * (m * (v**2).sum(axis=1)).sum(), rel=1e-12)
    assert e["kinetic_rotational"] == pytest.approx(0.5 * (0.4 * m * r**2 * (w**2).sum(axis=1)).sum(), rel=1e-12)
    assert e["contacts"] == len(settled.contacts()["i"]) + len(settled.wall_contacts()["i"])
    assert e["elastic"] > 0 and 0 < e["max_overlap_ratio"] < 0.1


def test_analyses_on_the_current_state(settled):
    sim = settled
    ours = sim.analyses()
    assert set(ours) == {"solid_fraction", "solid_fraction_grains", "coordination", "coordination_no_rattlers",
                         "coordination_no_rattlers_4", "coordination_grains"}
    assert sim.analyze("solid_fraction", z_range=[0, 0.002]) == {
        "solid_fraction": ours["solid_fraction"], "solid_fraction_grains": ours["solid_fraction_grains"]}
    # The solid fraction by hand: sphere caps between z = 0 and 0.002 over the box's base.
    z, r = sim.positions[:, 2], sim.radii
    lo, hi = np.maximum(0 - z, -r), np.minimum(0.002 - z, r)
    cap = lambda t: np.pi * (r**2 * t - t**3 / 3)  # noqa: E731
    solid = np.where(hi > lo, cap(hi) - cap(lo), 0).sum()
    assert ours["solid_fraction"] == pytest.approx(solid / (0.006 * 0.006 * 0.002), rel=1e-12)
    named = sim.analyze("porosity", name="pores", z_range=[0.0005, 0.0015], points=2000, seed=3)
    assert set(named) == {"pores", "pores_standard_error", "pores_points", "pores_exact", "pores_grains"}
    assert named["pores_points"] == 2000 and abs(named["pores"] - named["pores_exact"]) < 5 * named["pores_standard_error"]
    assert sim.analyze("kinetic_energy")["kinetic_energy"] == pytest.approx(
        sim.energies()["kinetic_translational"] + sim.energies()["kinetic_rotational"], rel=1e-12)


def test_contacts_after_a_resume_need_a_step(settled, tmp_path):
    settled.checkpoint(tmp_path / "c.tsbk")
    sim = tsubu.Simulation.resume(tmp_path / "c.tsbk")
    with pytest.raises(RuntimeError, match="step once first"):
        sim.contacts()
    assert np.isnan(sim.energies()["elastic"])
    sim.step()
    assert len(sim.contacts()["i"]) >= 10


def test_rolling_spring_of_the_contacts(bed):
    """With a rolling law each contact also gives its rolling spring, turned with the pair
    (seen from the smaller index, as its force); without one there is no such array."""
    assert "rolling_spring" not in tsubu.Simulation(bed).contacts()
    sim = tsubu.Simulation(bed, overrides={"contact.default.rolling": "epsd", "contact.default.rolling_friction": 0.2})
    sim.advance_to(0.004)
    pairs, walls = sim.contacts(), sim.wall_contacts()
    for c in (pairs, walls):
        assert c["rolling_spring"].shape == c["force"].shape
    springs = np.concatenate([pairs["rolling_spring"], walls["rolling_spring"]])
    assert (np.abs(springs).max(axis=1) > 0).any()
    # In the contact plane: no twist about the normal, the pair's line of centres (the pairs
    # that touch inside the box; the others touch across a periodic side).
    d = sim.positions[pairs["j"]] - sim.positions[pairs["i"]]
    inside = np.linalg.norm(d, axis=1) < sim.radii[pairs["i"]] + sim.radii[pairs["j"]]
    assert inside.sum() >= 10
    along = np.abs((pairs["rolling_spring"] * d).sum(axis=1))[inside] / np.linalg.norm(d[inside], axis=1)
    assert (along <= 1e-9 * np.abs(pairs["rolling_spring"]).max()).all()
