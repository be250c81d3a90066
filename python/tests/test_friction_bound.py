"""The two readings of Sota & Watanabe's friction law (docs/engine.md, "Tangential models"),
checked on every contact of the small bed: with friction_bound = "total" the whole tangential
force is within mu times the elastic (Hertz) normal force, and friction = 0 is frictionless;
as printed ("spring") the dashpot comes on top, so friction = 0 still transmits a
tangential force."""

import numpy as np
import pytest

import tsubu

from conftest import bed_text

E, NU, MU = 1e7, 0.3, 0.5  # bed.toml's glass and friction
E_STAR = E / (2 * (1 - NU**2))  # two grains of one material; a grain on the same-material floor


def tangential_and_elastic(sim):
    """Per contact (pairs, then floor contacts): |F_t| and the Hertz force K delta^{3/2}."""
    x, r = sim.positions, sim.radii
    (lo, hi) = np.array(sim.domain[0]), np.array(sim.domain[1])
    box = hi - lo
    pairs, walls = sim.contacts(), sim.wall_contacts()
    branch = x[pairs["j"]] - x[pairs["i"]]
    branch[:, :2] -= box[:2] * np.round(branch[:, :2] / box[:2])  # periodic in x and y
    n = np.vstack([branch / np.linalg.norm(branch, axis=1)[:, None], np.tile([0.0, 0.0, -1.0], (len(walls["i"]), 1))])
    f = np.vstack([pairs["force"], walls["force"]])
    r_eff = np.concatenate([r[pairs["i"]] * r[pairs["j"]] / (r[pairs["i"]] + r[pairs["j"]]), r[walls["i"]]])
    delta = np.concatenate([pairs["overlap"], walls["overlap"]])
    f_t = f - (f * n).sum(axis=1)[:, None] * n
    elastic = 4 / 3 * E_STAR * np.sqrt(r_eff) * delta**1.5
    return np.linalg.norm(f_t, axis=1), elastic


def bed(tmp_path, integrator, bound, friction=MU):
    text = bed_text(integrator).replace('tangential = "mindlin"', f'tangential = "mindlin"\nfriction_bound = "{bound}"')
    path = tmp_path / "bed.toml"
    path.write_text(text.replace(f"friction = {MU}", f"friction = {friction}"))
    return tsubu.Simulation(path)


# Velocity Verlet's contact forces come from the positions sim.positions holds: the bound
# holds to round-off. A block step's come from the positions predicted for its evaluation,
# which the corrector then moves by its fourth-order term (a relative 1e-6 of the overlap
# here), so the check from outside has that much slack; the law's own bound is exact.
@pytest.mark.parametrize("integrator, slack", [("velocity_verlet", 1e-9), ("block_hermite", 1e-5)])
def test_the_bounded_law_keeps_every_contact_within_coulomb(tmp_path, integrator, slack):
    sim = bed(tmp_path, integrator, "total")
    checked = 0
    for t in np.arange(0.0015, 0.00401, 0.00025):  # pouring, impacts and sliding
        sim.advance_to(t)
        f_t, elastic = tangential_and_elastic(sim)
        assert (f_t <= MU * elastic * (1 + slack) + 1e-15).all(), (f_t / (MU * elastic)).max()
        checked += len(f_t)
    assert checked > 100


def test_as_printed_the_dashpot_comes_on_top_of_the_bound(tmp_path):
    sim = bed(tmp_path, "velocity_verlet", "spring")
    sim.advance_to(0.004)
    f_t, elastic = tangential_and_elastic(sim)
    assert (f_t > MU * elastic * (1 + 1e-6)).any()


@pytest.mark.parametrize("bound, frictionless", [("total", True), ("spring", False)])
def test_zero_friction(tmp_path, bound, frictionless):
    sim = bed(tmp_path, "velocity_verlet", bound, friction=0.0)
    sim.advance_to(0.004)
    f_t, _ = tangential_and_elastic(sim)
    scale = np.abs(sim.forces).max()
    if frictionless:
        assert (f_t <= 1e-12 * scale).all()
    else:
        assert f_t.max() > 1e-6 * scale  # the tangential dashpot, uncapped
