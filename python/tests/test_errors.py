"""The engine's errors as Python exceptions carrying the command line's messages."""

import numpy as np
import pytest

import tsubu
from conftest import bed_text


def test_scenario_errors_name_file_line_and_key(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(bed_text().replace("dt = 5e-6", "dt = -5e-6"))
    with pytest.raises(tsubu.ScenarioError) as e:
        tsubu.Simulation(path)
    assert isinstance(e.value, ValueError)
    assert str(e.value).startswith(f"{path}:6: simulation.dt: ")


def test_scenario_text_errors_name_the_text():
    with pytest.raises(tsubu.ScenarioError, match=r"^<scenario text>:18: materials\[0\]\.density: must be > 0, got -1$"):
        tsubu.Simulation(bed_text().replace("density = 2500", "density = -1"))


def test_unknown_keys_and_missing_files():
    with pytest.raises(tsubu.ScenarioError, match=r"no-such\.toml:0: cannot open the scenario file"):
        tsubu.Simulation("no-such.toml")


def test_overrides_use_the_command_lines_parser(bed):
    sim = tsubu.Simulation(bed, overrides={"simulation.dt": 2e-6, "search.sort_every": 0, "simulation.integrator": "symplectic_euler"})
    assert (sim.dt, sim.integrator) == (2e-6, "symplectic_euler")
    assert tsubu.Simulation(bed, overrides=["simulation.dt=2e-6"]).dt == 2e-6
    # NumPy values and str as TOML strings (quotes escaped).
    sim = tsubu.Simulation(bed, overrides={"simulation.dt": np.float64(2e-6), "simulation.seed": np.int64(6),
                                           "simulation.gravity": np.array([0.0, 0.0, -9.81]),
                                           "simulation.name": 'bed "two"'})
    assert (sim.dt, sim.name) == (2e-6, 'bed "two"')
    with pytest.raises(tsubu.ScenarioError, match=r"^--set simulation\.dt=x:1: simulation\.dt: the value is not valid TOML"):
        tsubu.Simulation(bed, overrides=["simulation.dt=x"])
    with pytest.raises(tsubu.ScenarioError, match="simulation.integrator"):
        tsubu.Simulation(bed, overrides={"simulation.integrator": "leapfrog"})
    with pytest.raises(TypeError, match="TOML value"):
        tsubu.Simulation(bed, overrides={"simulation.dt": object()})


def test_a_grain_that_leaves_the_box_is_a_numerical_error(bed):
    sim = tsubu.Simulation(bed)
    sim.positions[0] = [0.003, 0.003, 0.02]  # above the box's top, which is not periodic
    with pytest.raises(tsubu.NumericalError, match=r"step 1, t = 5e-06 s: particle id \d+ left the domain"):
        sim.step(5)
    assert sim.step_count == 1  # the failing state, after the drift of step 1, is kept for inspection
    with pytest.raises(RuntimeError, match="the run failed and cannot go on"):
        sim.step()


def test_an_overlap_beyond_the_limit_is_a_numerical_error(bed):
    sim = tsubu.Simulation(bed)
    sim.positions[1] = sim.positions[0] + np.array([sim.radii[0], 0, 0])  # half inside grain 0
    with pytest.raises(tsubu.NumericalError, match="overlap"):
        sim.step()


def test_bad_arguments(bed):
    sim = tsubu.Simulation(bed)
    sim.step(3)
    with pytest.raises(ValueError, match="cannot go back to step 0"):
        sim.advance_to(0)
    with pytest.raises(ValueError, match="n must be >= 0"):
        sim.step(-1)
    with pytest.raises(tsubu.ScenarioError, match=r"^analyze\(\):1: type: "):
        sim.analyze("density")
    with pytest.raises(tsubu.ScenarioError, match=r"^analyze\(\):2: z_range: must be \[z_low, z_high\]"):
        sim.analyze("solid_fraction", z_range=[0.002, 0.001])
    with pytest.raises(tsubu.ScenarioError, match=r"^analyze\(\):2: pointz: unknown key"):
        sim.analyze("porosity", pointz=10)
