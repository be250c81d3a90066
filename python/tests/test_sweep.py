"""tsubu.sweep: a 2 x 2 grid of small inflow runs with 2 jobs, skipping, resuming after a kill
and after Ctrl-C, failed cases, and bad sweep files (about half a minute in all)."""
import csv
import errno
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

import tsubu.sweep
from tsubu.runs import lock_holder, read_table
from tsubu.sweep import SweepError, load_sweep, run_sweep, toml_value

ROOT = Path(__file__).resolve().parents[2]
TSUBU = os.environ.get("TSUBU_BINARY", str(ROOT / "build" / "tsubu"))
SCENARIO = ROOT / "tests" / "scenarios" / "inflow_small.toml"
ENV = {**os.environ, "TSUBU_BINARY": TSUBU}  # and PYTHONPATH: the built package (CTest)
GRID = {"particles.0.solid_fraction": [0.1, 0.05], "simulation.seed": [3, 4]}
CASES = ["solid_fraction=0.1,seed=3", "solid_fraction=0.1,seed=4", "solid_fraction=0.05,seed=3",
         "solid_fraction=0.05,seed=4"]


def write_sweep(path, output, grid=GRID, **keys):
    """A sweep file over inflow_small.toml run to t = 0.4 s (20000 steps, about a second)."""
    sets = {"simulation.duration": 0.4, **keys.pop("set", {})}
    lines = [f'scenario = "{SCENARIO}"', f'output = "{output}"', *(f"{k} = {toml_value(v)}" for k, v in keys.items()),
             "[set]", *(f'"{k}" = {toml_value(v)}' for k, v in sets.items()),
             "[grid]", *(f'"{k}" = {toml_value(v)}' for k, v in grid.items())]
    path.write_text("\n".join(lines) + "\n")
    return path


def sweep(*args, **popen):
    return subprocess.run([sys.executable, "-m", "tsubu.sweep", *map(str, args)], env=ENV, capture_output=True,
                          text=True, **popen)


def results(root):
    with open(root / "results.csv") as f:
        return {row["case"]: row for row in csv.DictReader(f)}


def wait_for(condition, what, timeout=120):
    end = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < end, f"timed out waiting for {what}"
        time.sleep(0.01)


@pytest.fixture(scope="module")
def grid_run(tmp_path_factory):
    """The 2 x 2 grid run with 2 jobs, uninterrupted: the reference of the other tests."""
    root = tmp_path_factory.mktemp("sweep")
    file = write_sweep(root / "grid.toml", root / "out", jobs=2)
    done = sweep(file)
    assert done.returncode == 0, done.stderr
    return file, root / "out", done


def test_grid_runs_every_case(grid_run):
    file, out, done = grid_run
    assert sorted(p.name for p in out.iterdir() if p.is_dir() and p.name != "logs") == sorted(CASES)
    table = results(out)
    assert sorted(table) == sorted(CASES)
    for name, row in table.items():
        summary = json.loads((out / name / "run.json").read_text())
        assert row["status"] == summary["status"] == "ok" and row["stop_reason"] == "duration"
        assert int(row["steps"]) == summary["steps"] == 20000
        assert float(row["wall_time_s"]) == summary["wall_time_s"]
        assert int(row["particle_force_evaluations"]) == summary["particle_force_evaluations"] > 0
        assert float(row["porosity"]) == summary["results"]["porosity"]
        seed, phi = int(row["simulation.seed"]), float(row["particles.0.solid_fraction"])
        assert name == f"solid_fraction={phi},seed={seed}" and summary["results"]["inflow_phi_0"] == phi
    read = read_table(out / "results.csv")  # the sweep's own table, text columns and all
    assert sorted(read["case"]) == sorted(CASES) and read["steps"].tolist() == [20000] * 4
    assert read["porosity"].tolist() == [float(table[name]["porosity"]) for name in read["case"]]
    assert "sweep: 4 of 4 cases finished" in done.stderr
    assert re.search(r"sweep: 4 done, 0 running, 0 left, 0 failed; elapsed \S+, ETA 0s", done.stderr)
    assert "2 running" in done.stderr  # two at a time


def test_rerun_skips_finished_cases(grid_run):
    file, out, _ = grid_run
    before = {c: (out / c / "run.json").stat().st_mtime_ns for c in CASES}
    done = sweep(file, "--dry-run")
    assert done.returncode == 0 and done.stdout.count(": skip (ok)") == 4 and "0 to run" in done.stdout
    done = sweep(file)
    assert done.returncode == 0 and "sweep: 4 of 4 cases finished" in done.stderr
    assert {c: (out / c / "run.json").stat().st_mtime_ns for c in CASES} == before
    assert all(row["status"] == "ok" for row in results(out).values())


def same_outputs(a, b):
    """The case folders a and b hold the same series, track, frames (every file but the run's
    identity, lock and checkpoints) and results."""
    def outputs(folder):
        return sorted(p.relative_to(folder) for p in folder.rglob("*") if p.is_file() and p.name not in
                      ("run.json", ".tsubu-run", ".tsubu-lock") and "checkpoint" not in p.relative_to(folder).parts)
    assert outputs(a) == outputs(b) and len(outputs(a)) > 10
    for name in outputs(a):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    ra, rb = (json.loads((p / "run.json").read_text()) for p in (a, b))
    assert ra["results"] == rb["results"] and ra["steps"] == rb["steps"] and ra["status"] == rb["status"] == "ok"


def test_killed_case_resumes(grid_run, tmp_path):
    """A sweep and its run killed (SIGKILL) after a checkpoint: the next sweep resumes the case
    and it ends with the same outputs as the uninterrupted case."""
    _, reference, _ = grid_run
    file = write_sweep(tmp_path / "one.toml", tmp_path / "out", grid={"particles.0.solid_fraction": [0.1],
                       "simulation.seed": [3]}, set={"output.checkpoint_every_steps": 500})
    case = tmp_path / "out" / CASES[0]
    proc = subprocess.Popen([sys.executable, "-m", "tsubu.sweep", str(file)], env=ENV, stderr=subprocess.DEVNULL)
    wait_for(lambda: any((case / "checkpoint").glob("*.tsbk")), "the first checkpoint")
    proc.kill()
    proc.wait()
    pid = int(re.match(r"pid (\d+)", (case / ".tsubu-lock").read_text()).group(1))
    os.kill(pid, signal.SIGKILL)
    wait_for(lambda: not Path(f"/proc/{pid}").exists() or "Z" in Path(f"/proc/{pid}/stat").read_text().split()[2],
             "the killed run to end")
    assert not (case / "run.json").exists(), "the run ended before it was killed"
    done = sweep(file)
    assert done.returncode == 0, done.stderr
    log = (tmp_path / "out" / "logs" / f"{CASES[0]}.log").read_text()
    assert f"resume {case} --threads 1" in log
    same_outputs(case, reference / CASES[0])


def test_a_sweep_locks_its_folder_and_waits_for_a_case_another_tsubu_runs(tmp_path):
    """Issue 25, item 4: a second sweep into the folder of a running one exits 2 naming it and
    touches nothing; a sweep restarted after a SIGKILL, while the killed sweep's run still
    goes on, waits for that run instead of failing the case (both exited 1 before, with
    finished cases recorded as failed and one logs/ for both). The run lasts about 8 s on an idle
    machine: at 3 s, two starts of the sweep on an overloaded one outlasted it."""
    file = write_sweep(tmp_path / "one.toml", tmp_path / "out", grid={"particles.0.solid_fraction": [0.1],
                       "simulation.seed": [3]}, set={"simulation.duration": 3.0})
    case, log = tmp_path / "out" / CASES[0], tmp_path / "out" / "logs" / f"{CASES[0]}.log"
    first = subprocess.Popen([sys.executable, "-m", "tsubu.sweep", str(file)], env=ENV, stderr=subprocess.DEVNULL)
    wait_for(lambda: (case / ".tsubu-run").exists(), "the case's run to start")
    second = sweep(file)
    assert second.returncode == 2, second.stderr
    assert f"out: in use by another sweep (pid {first.pid} on " in second.stderr
    assert log.read_text().count("$ ") == 1
    first.kill()  # its run goes on: a session of its own
    first.wait()
    assert not (case / "run.json").exists(), "the run ended before the sweep was killed: make it longer"
    done = sweep(file)
    assert done.returncode == 0, done.stderr
    assert f"sweep: {CASES[0]}: running in another tsubu (pid " in done.stderr
    assert results(tmp_path / "out")[CASES[0]]["status"] == "ok"
    assert log.read_text().count("$ ") == 1  # the case was not run again


def test_interrupt_stops_runs_with_checkpoints(grid_run, tmp_path):
    """SIGINT to the sweep: its runs stop with a checkpoint (exit 4, status interrupted in
    results.csv); the next sweep resumes them to the same outputs as uninterrupted runs."""
    _, reference, _ = grid_run
    file = write_sweep(tmp_path / "two.toml", tmp_path / "out", grid={"particles.0.solid_fraction": [0.1, 0.05],
                       "simulation.seed": [3]}, jobs=2)
    cases = [tmp_path / "out" / CASES[0], tmp_path / "out" / CASES[2]]
    proc = subprocess.Popen([sys.executable, "-m", "tsubu.sweep", str(file)], env=ENV, stderr=subprocess.PIPE,
                            text=True)
    wait_for(lambda: all((c / "frames" / "frame_00001.vtu").exists() for c in cases), "both runs to write frame 1")
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 4, err
    assert "asking 2 runs to stop with a checkpoint" in err and "run the same command again to continue" in err
    statuses = {row["status"] for row in results(tmp_path / "out").values()}
    assert statuses <= {"interrupted", "ok"} and "interrupted" in statuses
    done = sweep(file)
    assert done.returncode == 0, done.stderr
    for case in cases:
        same_outputs(case, reference / case.name)


def test_failed_case_is_reported_not_retried(grid_run, tmp_path):
    """A case whose run failed (run.json status failed) is reported and left alone;
    --retry-failed runs it again from the start. A case tsubu refuses fails with its message."""
    _, reference, _ = grid_run
    out = tmp_path / "out"
    file = write_sweep(tmp_path / "f.toml", out, grid={"particles.0.solid_fraction": [0.1], "simulation.seed": [3]})
    shutil.copytree(reference / CASES[0], out / CASES[0])
    summary = json.loads((out / CASES[0] / "run.json").read_text())
    (out / CASES[0] / "run.json").write_text(json.dumps({**summary, "status": "failed", "message": "step 7: NaN"}))
    done = sweep(file)
    assert done.returncode == 1 and "not finished: solid_fraction=0.1,seed=3" in done.stderr
    assert results(out)[CASES[0]]["status"] == "failed" and results(out)[CASES[0]]["message"] == "step 7: NaN"
    assert not (out / "logs" / f"{CASES[0]}.log").exists()
    done = sweep(file, "--retry-failed")
    assert done.returncode == 0, done.stderr
    assert "--overwrite" in (out / "logs" / f"{CASES[0]}.log").read_text()
    same_outputs(out / CASES[0], reference / CASES[0])

    # An interrupted case whose resume fails (a frame deleted): failed, with tsubu's message.
    (out / CASES[0] / "run.json").write_text(json.dumps({**summary, "status": "interrupted"}))
    next((out / CASES[0]).glob("*/frame_00003.vtu")).unlink()
    done = sweep(file)
    assert done.returncode == 1
    row = results(out)[CASES[0]]
    assert row["status"] == "failed" and "tsubu exited with code 1" in row["message"]
    assert "frame_00003.vtu" in row["message"]

    bad = write_sweep(tmp_path / "bad.toml", tmp_path / "bad", grid={"simulation.dt": [-1.0]})
    done = sweep(bad)
    assert done.returncode == 1
    row = results(tmp_path / "bad")["dt=-1.0"]
    assert row["status"] == "failed" and "tsubu exited with code 2" in row["message"]
    assert "simulation.dt" in row["message"] and "sweep: dt=-1.0: failed:" in done.stderr
    done = sweep(bad, "--dry-run")
    assert done.returncode == 1 and "refused by tsubu check:" in done.stdout


def test_api_takes_a_dict(tmp_path, capsys):
    cases = run_sweep({"scenario": str(SCENARIO), "output": str(tmp_path / "out"),
                       "cases": [{"simulation": {"duration": 0.01}}, {"simulation.duration": 0.02}]},
                      jobs=2, tsubu=TSUBU, progress=None)
    assert [c.name for c in cases] == ["duration=0.01", "duration=0.02"]
    assert [c.status for c in cases] == ["ok", "ok"] and cases[1].summary["steps"] == 1000
    assert sorted(results(tmp_path / "out")) == ["duration=0.01", "duration=0.02"]


def test_a_full_disk_stops_the_runs_with_a_checkpoint(tmp_path, monkeypatch, capsys):
    """results.csv cannot be written once the first case ends (a full disk): the sweep died in
    a traceback, left results.csv.tmp and the other run running."""
    out = tmp_path / "out"
    file = tmp_path / "full.toml"
    file.write_text(f'scenario = "{SCENARIO}"\noutput = "{out}"\njobs = 2\n'
                    '[set]\n"simulation.dt" = 1e-6\n"output.vtk_interval" = 0\n'
                    '[[cases]]\n"simulation.duration" = 0.002\n[[cases]]\n"simulation.duration" = 100\n')
    real_fsync, calls = os.fsync, []

    def fsync(fd):  # results.csv's second write (after a case) finds the disk full
        calls.append(fd)
        if len(calls) > 1:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real_fsync(fd)

    monkeypatch.setattr(tsubu.sweep.os, "fsync", fsync)
    assert tsubu.sweep.main([str(file), "--tsubu", TSUBU]) == 5
    assert capsys.readouterr().err.splitlines()[-1] == (
        f"error: cannot write {out / 'results.csv'}: No space left on device; 1 run under way stopped, keeping the "
        "newest checkpoint; make room, then run the same command again to continue")
    assert not (out / "results.csv.tmp").exists()
    assert [row["status"] for row in results(out).values()] == ["pending", "pending"]  # the last good one
    long = out / "duration=100"
    assert lock_holder(long) is None, "a run was left running"
    assert json.loads((long / "run.json").read_text())["status"] == "interrupted"
    assert list((long / "checkpoint").glob("step_*.tsbk"))


@pytest.mark.parametrize("text, message", [
    ('output = "x"\n', r"scenario: required: the path of the base scenario"),
    ('scenario = "missing.toml"\n[grid]\n"a.b" = [1]\n', r"scenario: no such file: .*missing.toml"),
    ('scenario = "S"\nfoo = 1\n[grid]\n"a.b" = [1]\n', r"foo: unknown key \(allowed: scenario, output, jobs"),
    ('scenario = "S"\n', r"grid: a sweep needs a \[grid\] and/or \[\[cases\]\]"),
    ('scenario = "S"\n[grid]\n"simulation.dt" = 1e-6\n', r"grid.simulation.dt: a grid parameter takes a non-empty"),
    ('scenario = "S"\n[grid]\n"simulation.dt" = []\n', r"grid.simulation.dt: a grid parameter takes a non-empty"),
    ('scenario = "S"\njobs = 0\n[grid]\n"a.b" = [1]\n', r"jobs: must be an integer of at least 1, got 0"),
    ('scenario = "S"\nthreads = "2"\n[grid]\n"a.b" = [1]\n', r"threads: must be an integer of at least 1"),
    ('scenario = "S"\ncases = 3\n', r"cases: must be an array of tables"),
    ('scenario = "S"\n[[cases]]\n', r"cases.0: an empty case"),
    ('scenario = "S"\n[grid]\n"a.b" = [1]\n[[cases]]\n"a.b" = 2\n', r"cases.0.a.b: also a grid parameter"),
    ('scenario = "S"\n[grid]\n"a.b" = ["x/y", "x_y"]\n', r"cases: two cases give the folder 'b=x_y'"),
    ('scenario = "S"\n[grid]\n"a.b" = [1979-05-27]\n', r"a.b: .* is not a value --set takes"),
    ('scenario = "S"\n[grid\n', r"not valid TOML"),
])
def test_bad_sweep_files(tmp_path, text, message):
    file = tmp_path / "s.toml"
    file.write_text(text.replace('"S"', f'"{SCENARIO}"'))
    with pytest.raises(SweepError, match=rf"^{re.escape(str(file))}: {message}"):
        load_sweep(file)


def test_bad_sweep_file_exits_2(tmp_path):
    file = tmp_path / "s.toml"
    file.write_text(f'scenario = "{SCENARIO}"\n[grid]\n"simulation.seed" = 3\n')
    done = sweep(file)
    assert done.returncode == 2 and not (tmp_path / "out").exists()
    assert done.stderr == f"error: {file}: grid.simulation.seed: a grid parameter takes a non-empty array of values\n"
    file.write_text(f'scenario = "{SCENARIO}"\n[grid]\n"simulation.seed" = [3]\n')
    done = sweep(file, "--jobs", "0")
    assert done.returncode == 2 and done.stderr == "error: --jobs: must be an integer of at least 1, got 0\n"


def test_only_selects_cases(grid_run, tmp_path):
    """--only runs the cases with the given parameter values; a key the sweep does not vary is refused."""
    file = write_sweep(tmp_path / "grid.toml", tmp_path / "out")
    done = sweep(file, "--dry-run", "--only", "simulation.seed=4", "--only", "particles.0.solid_fraction=0.05")
    assert done.returncode == 0, done.stderr
    assert "4 cases, 1 selected, 1 to run" in done.stdout and "solid_fraction=0.05,seed=4:" in done.stdout
    assert "seed=3" not in done.stdout
    done = sweep(file, "--only", "simulation.dt=1e-6")
    assert done.returncode == 2 and "--only simulation.dt: not a parameter of this sweep" in done.stderr
    finished, out, _ = grid_run
    done = sweep(finished, "--only", "simulation.seed=4")
    assert done.returncode == 0 and "sweep: 2 of 2 cases finished" in done.stderr, done.stderr
    assert [row["status"] for row in results(out).values()] == ["ok"] * 4, "results.csv keeps the cases left out"


def test_only_takes_a_bare_word_as_the_string_it_spells():
    """--only KEY=word (as a shell leaves KEY="word") selects the cases whose string parameter is
    that word; a word no case has is refused, naming the values."""
    cases = [SimpleNamespace(params={"contact.default.friction_bound": bound, "simulation.seed": seed})
             for bound in ("total", "spring") for seed in (1, 2)]
    bare = tsubu.sweep.select_cases(cases, ["contact.default.friction_bound=spring"])
    quoted = tsubu.sweep.select_cases(cases, ['contact.default.friction_bound="spring"'])
    assert bare == quoted and [c.params["simulation.seed"] for c in bare] == [1, 2]
    with pytest.raises(SweepError, match='no case matches; contact.default.friction_bound takes "total", "spring"'):
        tsubu.sweep.select_cases(cases, ["contact.default.friction_bound=sprung"])


def test_only_that_matches_no_case_lists_the_values(tmp_path):
    """--only with a value no case has ended "0 of 0 cases finished", exit 0."""
    file = write_sweep(tmp_path / "grid.toml", tmp_path / "out")
    done = sweep(file, "--only", "simulation.seed=5")
    assert done.returncode == 2 and not (tmp_path / "out").exists()
    assert done.stderr == "error: --only simulation.seed=5: no case matches; simulation.seed takes 3, 4\n"
    done = sweep(file, "--dry-run", "--only", "simulation.seed=4", "--only", "particles.0.solid_fraction=0.2")
    assert done.returncode == 2 and done.stderr == (
        "error: --only simulation.seed=4 particles.0.solid_fraction=0.2: no case matches; simulation.seed takes 3, 4;"
        " particles.0.solid_fraction takes 0.1, 0.05\n")


def test_a_tsubu_that_is_not_an_executable_is_refused(tmp_path):
    """--tsubu or $TSUBU_BINARY naming no executable ran the build's tsubu instead."""
    file = write_sweep(tmp_path / "grid.toml", tmp_path / "out")
    missing = tmp_path / "no-tsubu"
    done = sweep(file, "--tsubu", missing)
    assert done.returncode == 2 and not (tmp_path / "out").exists()
    assert done.stderr == (f"error: --tsubu {missing}: names no executable file (nor a command on the PATH); "
                           "give the path of tsubu, e.g. build/tsubu\n")
    done = subprocess.run([sys.executable, "-m", "tsubu.sweep", str(file), "--dry-run"],
                          env={**ENV, "TSUBU_BINARY": str(SCENARIO)}, capture_output=True, text=True)
    assert done.returncode == 2 and done.stderr.startswith(f"error: TSUBU_BINARY {SCENARIO}: names no executable file")


EXAMPLE_SWEEPS = {"ci": 4, "fig5-6": 24, "fig5-6-stop": 24, "vacuum": 18, "finite-size": 9, "fig5-6-hindered": 6,
                  "rcp-mono": 3, "fig7-rest": 288, "fig7-stop": 288, "box": 4, "fig8": 2, "rcp": 24, "fig7-hindered": 36,
                  "readings": 12, "integrators": 80}


def test_every_example_sweep_is_checked():
    folder = ROOT / "examples" / "sedimentation" / "sweeps"
    assert sorted(p.stem for p in folder.glob("*.toml")) == sorted(EXAMPLE_SWEEPS)


@pytest.mark.parametrize("name, count", EXAMPLE_SWEEPS.items())
def test_example_sweeps_dry_run(tmp_path, name, count):
    """The sedimentation sweeps are valid: every case passes `tsubu check` (nothing is run)."""
    done = sweep(ROOT / "examples" / "sedimentation" / "sweeps" / f"{name}.toml", "--dry-run", cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"{count} cases, {count} to run" in done.stdout and "refused" not in done.stdout
    assert not (tmp_path / "out").exists()
