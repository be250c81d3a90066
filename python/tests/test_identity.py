"""A run driven from Python gives the command line's bits, and checkpoints continue it
bit-identically: compared through the CLI's track.csv (17 digits: every double exactly), the
CLI's final checkpoint, and checkpoints written and resumed by the binding."""

import csv
import subprocess

import numpy as np
import pytest

import tsubu


def by_id(sim):
    """positions, velocities, spins and forces in the order of the particle ids."""
    order = np.argsort(sim.ids)
    return {name: getattr(sim, name)[order].copy() for name in ("positions", "velocities", "spins", "forces")}


def assert_same_bits(a, b):
    for name in a:
        assert a[name].tobytes() == b[name].tobytes(), name


def run_cli(binary, scenario, out, *sets):
    args = [binary, "run", str(scenario), "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True, capture_output=True)


@pytest.mark.parametrize("integrator", ["velocity_verlet", "symplectic_euler", "block_hermite"])
def test_python_run_equals_cli_run(tmp_path, tsubu_binary, integrator):
    from conftest import bed_text

    scenario = tmp_path / "bed.toml"
    scenario.write_text(bed_text(integrator))
    sets = ["output.track=[0, 5, 17]", "output.track_interval=0", "output.checkpoint_every_steps=100000"]
    run_cli(tsubu_binary, scenario, tmp_path / "out", *sets)

    sim = tsubu.Simulation(scenario, overrides=sets)
    # The CLI writes track.csv rows at every step: compare a middle step and the last.
    with open(tmp_path / "out" / "track.csv") as f:
        rows = list(csv.DictReader(f))
    middle = 300
    for steps in (middle, round(sim.duration / sim.dt)):
        sim.advance_to(steps * sim.dt)
        assert sim.step_count == steps
        for row in (r for r in rows if float(r["time"]) == sim.time):
            i = int(np.flatnonzero(sim.ids == int(row["id"]))[0])
            assert [float(row[k]) for k in ("x", "y", "z")] == sim.positions[i].tolist()
            assert [float(row[k]) for k in ("vx", "vy", "vz")] == sim.velocities[i].tolist()
            assert [float(row[k]) for k in ("wx", "wy", "wz")] == sim.spins[i].tolist()
    # Every particle: the CLI's final checkpoint, read back by the binding.
    cli_end = tsubu.Simulation.resume(tmp_path / "out")
    assert cli_end.step_count == sim.step_count
    assert_same_bits(by_id(sim), by_id(cli_end))


def test_python_run_with_inflow_equals_cli_run(tmp_path, tsubu_binary, inflow_scenario):
    sets = ["simulation.duration=0.06"]
    run_cli(tsubu_binary, inflow_scenario, tmp_path / "out", *sets)
    sim = tsubu.Simulation(inflow_scenario, overrides={"simulation.duration": 0.06})
    sim.advance_to(sim.duration)
    cli_end = tsubu.Simulation.resume(tmp_path / "out")
    assert sim.particle_count == cli_end.particle_count > 0
    assert_same_bits(by_id(sim), by_id(cli_end))


@pytest.mark.parametrize("integrator", ["velocity_verlet", "block_hermite"])
def test_checkpoint_and_resume_continue_bit_identically(tmp_path, integrator):
    from conftest import bed_text

    text = bed_text(integrator)
    whole = tsubu.Simulation(text)
    whole.advance_to(0.003)

    first = tsubu.Simulation(text)
    first.step(275)  # not at a sort: the resumed lists come from the stored contacts
    first.checkpoint(tmp_path / "mid.tsbk")
    resumed = tsubu.Simulation.resume(tmp_path / "mid.tsbk")
    assert (resumed.step_count, resumed.time) == (275, first.time)
    assert_same_bits(by_id(first), by_id(resumed))
    resumed.advance_to(0.003)
    first.advance_to(0.003)  # writing the checkpoint did not disturb the run either
    assert_same_bits(by_id(whole), by_id(resumed))
    assert_same_bits(by_id(whole), by_id(first))


def test_resume_continues_a_cli_run_folder(tmp_path, tsubu_binary, bed):
    run_cli(tsubu_binary, bed, tmp_path / "half", "simulation.duration=0.002", "output.checkpoint_every_steps=100000")
    run_cli(tsubu_binary, bed, tmp_path / "whole", "output.checkpoint_every_steps=100000")
    sim = tsubu.Simulation.resume(tmp_path / "half")
    assert sim.step_count == 400
    sim.advance_to(0.004)
    assert_same_bits(by_id(sim), by_id(tsubu.Simulation.resume(tmp_path / "whole" / "checkpoint")))


def test_resume_of_a_damaged_or_missing_checkpoint_says_so(tmp_path, bed):
    bad = tmp_path / "bad.tsbk"
    bad.write_bytes(b"not a checkpoint")
    with pytest.raises(tsubu.CheckpointError):
        tsubu.Simulation.resume(bad)
    with pytest.raises(RuntimeError, match="no checkpoint in"):
        tsubu.Simulation.resume(tmp_path)
