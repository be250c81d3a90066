"""Shared fixtures of the binding's tests: the small bed scenario (bed.toml), in any of the
integrators, and the built command line (TSUBU_BINARY, set by CTest; python/CMakeLists.txt)."""

import os
import pathlib

import pytest

BED = pathlib.Path(__file__).with_name("bed.toml")


def bed_text(integrator="velocity_verlet"):
    """The bed scenario's text with the given integrator."""
    return BED.read_text().replace('integrator = "velocity_verlet"', f'integrator = "{integrator}"')


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
