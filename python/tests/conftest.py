"""Shared fixtures of the binding's tests: small scenarios written into the test's folder and
the built command line (TSUBU_BINARY, set by CTest; python/CMakeLists.txt)."""

import os
import pathlib
import textwrap

import pytest

# About 120 glass grains of 1-1.5 mm poured onto a floor in a periodic box, sorted along the
# Morton curve every 50 steps: contacts, wall contacts, friction and renumbering within a
# few hundred steps.
BED = textwrap.dedent(
    """\
    [simulation]
    duration = 0.004
    dt = 5e-6
    integrator = "{integrator}"
    gravity = [0.3, 0.1, -9.81]
    seed = 5

    [domain]
    lower = [0, 0, 0]
    upper = [0.006, 0.006, 0.01]
    periodic = ["x", "y"]

    [[materials]]
    name = "glass"
    density = 2500
    youngs_modulus = 1e7
    poisson = 0.3

    [contact.default]
    normal = "hertz_tsuji"
    tangential = "mindlin"
    restitution = 0.5
    friction = 0.5

    [[walls]]
    point = [0, 0, 0]
    normal = [0, 0, 1]
    material = "glass"

    [[particles]]
    source = "random"
    material = "glass"
    lower = [0, 0, 0]
    upper = [0.006, 0.006, 0.01]
    solid_fraction = 0.3
    distribution = {{ type = "uniform", d_min = 0.001, d_max = 0.0015 }}
    velocity = [0, 0, -0.3]

    [search]
    sort_every = 50

    [[analyses]]
    type = "solid_fraction"
    z_range = [0, 0.002]

    [[analyses]]
    type = "coordination"
    z_range = [0, 0.003]
    """
)


def bed_text(integrator="velocity_verlet"):
    return BED.format(integrator=integrator)


@pytest.fixture
def bed(tmp_path):
    """The bed scenario as a file (velocity Verlet)."""
    path = tmp_path / "bed.toml"
    path.write_text(bed_text())
    return path


@pytest.fixture
def block_bed(tmp_path):
    """The bed with the block-step Hermite integrator."""
    path = tmp_path / "block_bed.toml"
    path.write_text(bed_text("block_hermite"))
    return path


@pytest.fixture
def inflow_scenario():
    """A small inflow (grains enter during the run) from the C++ tests' scenarios."""
    return pathlib.Path(os.environ["TSUBU_SOURCE_DIR"]) / "tests" / "scenarios" / "inflow_small.toml"


@pytest.fixture
def tsubu_binary():
    return os.environ["TSUBU_BINARY"]
