#!/usr/bin/env python3
"""`mpirun -np N tsubu run|resume` (docs/parallel.md, "From the command line"): a checkpoint
of 3 processes resumed on 2 ends with one process's bits; so do a stop by SIGINT, then
resume; one process killed, or the whole job killed at a random time, then resume; runs with
rolling resistance (also on a grid given by `[parallel] counts`), a run with hindered
settling and an inflow (3 processes, resumed on 2); an open chute (3 processes, resumed on 2)
and an insertion; block steps sharing out their active grains (3 processes, resumed on 2; a
lost grain and a deep overlap failing alike). Counts that fit no grid, or [parallel] with
block steps, are refused (exit 2, naming the key); a failure on process 1 ends the whole job
with its message, process 0 recording it in run.json and keeping the series and checkpoints
as one process does; a failed force check on process 1 or 0 writes one process's frames,
the failing state's included; process 0 of a split run with moving walls builds its lists about as
often as one process; run.json of a split run says what each process held and sent.
(tools/compare_runs.py --new-launcher compares whole runs.)

    python3 tests/mpi/split_cli.py TSUBU "MPIRUN ARGS... -np"
"""
import json
import os
import pathlib
import random
import shlex
import signal
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
SETTLE = str(ROOT / "tests/scenarios/settle_mono.toml")
INFLOW = str(ROOT / "tests/scenarios/inflow_small.toml")
CHUTE = str(ROOT / "tests/scenarios/chute_open.toml")
BIN = str(ROOT / "tests/scenarios/insertion_bin.toml")
# A short poured bed with a checkpoint every 500 steps and frames.
SETS = ["simulation.duration=0.03", "output.checkpoint_every_steps=500", "output.vtk_interval=0.01"]
# The same bed poured for longer, for the faults: a kill up to 0.5 s after the first checkpoint
# lands before the end even on a fast machine (20000 steps take 1.4 s on 2 processes there).
LONG = ["simulation.duration=0.2"] + SETS[1:]
MAX_KILL_DELAY = 0.5
TIMEOUT = 600

failures = []


def check(ok, what):
    print(("ok: " if ok else "FAILED: ") + what, flush=True)
    if not ok:
        failures.append(what)


def tsubu_cmd(tsubu, launcher, processes, args):
    return [*launcher, str(processes), tsubu, *args] if processes > 1 else [tsubu, *args]


def run(tsubu, launcher, processes, args):
    r = subprocess.run(tsubu_cmd(tsubu, launcher, processes, args), capture_output=True, text=True, timeout=TIMEOUT)
    return r.returncode, r.stderr


def process_of(launcher_pid, rank):
    """The pid of process `rank` of the job the launcher `launcher_pid` started (Open MPI)."""
    for pid in subprocess.run(["pgrep", "-P", str(launcher_pid)], capture_output=True, text=True).stdout.split():
        if f"OMPI_COMM_WORLD_RANK={rank}".encode() in pathlib.Path(f"/proc/{pid}/environ").read_bytes().split(b"\0"):
            return int(pid)
    raise RuntimeError(f"no process {rank} under {launcher_pid}")


def with_sets(sets):
    return [a for s in sets for a in ("--set", s)]


def same_files(a, b, what, also_skip=()):
    """Every output and the final checkpoint's state (as tsubu export writes it: a checkpoint
    also holds the run id and the wall-clock time) of run folders a and b, but `also_skip`."""
    for folder in (a, b):
        subprocess.run([sys.argv[1], "export", str(folder), "--to", str(folder / "state")], check=True, capture_output=True)
    skip = {"run.json", ".tsubu-run", ".tsubu-lock", *also_skip}
    names = [{str(p.relative_to(f)) for p in f.rglob("*") if p.is_file() and p.name not in skip and p.suffix != ".tsbk"}
             for f in (a, b)]
    differ = sorted(names[0] ^ names[1]) + [n for n in sorted(names[0] & names[1]) if (a / n).read_bytes() != (b / n).read_bytes()]
    check(not differ, f"{what}: the same bytes as one process ({len(names[0])} files{'; differ: ' + ', '.join(differ) if differ else ''})")


def main():
    tsubu, launcher = sys.argv[1], shlex.split(sys.argv[2])
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        alone = tmp / "alone"
        code, err = run(tsubu, launcher, 1, ["run", SETTLE, "--out", str(alone)] + with_sets(SETS))
        assert code == 0, err

        # Three processes write checkpoints (the newest two are kept); the newest is lost; two resume.
        three = tmp / "three"
        code, err = run(tsubu, launcher, 3, ["run", SETTLE, "--out", str(three)] + with_sets(SETS))
        check(code == 0, f"a run on 3 processes ends with 0 ({code}: {err[-400:]})")
        split = json.loads((three / "run.json").read_text())
        loads = split.get("processes", {})
        check(loads.get("count") == 3 and sum(p["owned"] for p in loads["each"]) == split["particles"]
              and all(p["bytes_sent"] > 0 and p["arrangements"] > 0 for p in loads["each"])
              and len(loads["cuts"]["z"]) == 4 and loads["cuts"]["z"] == sorted(loads["cuts"]["z"]),
              f"its run.json says what each process held and sent ({loads})")
        check("processes" not in json.loads((alone / "run.json").read_text()), "one process's run.json has no processes")
        checkpoints = sorted((three / "checkpoint").glob("step_*.tsbk"))
        check(len(checkpoints) == 2, f"it wrote checkpoints ({len(checkpoints)})")
        checkpoints[-1].unlink()
        code, err = run(tsubu, launcher, 2, ["resume", str(three)])
        check(code == 0, f"its checkpoint resumes on 2 processes ({code}: {err[-400:]})")
        same_files(alone, three, "3 processes, resumed on 2")

        # SIGINT to process 0 alone: all processes agree to stop; a checkpoint, "interrupted".
        stopped = tmp / "stopped"
        p = subprocess.Popen(tsubu_cmd(tsubu, launcher, 2, ["run", SETTLE, "--out", str(stopped)] + with_sets(SETS)),
                             stderr=subprocess.PIPE, text=True)
        while not (stopped / "series.csv").exists() or len((stopped / "series.csv").read_text().splitlines()) < 3:
            time.sleep(0.05)
            assert p.poll() is None, p.stderr.read()
        rank0 = subprocess.run(["pgrep", "-P", str(p.pid), "-f", "tsubu"], capture_output=True, text=True).stdout.split()
        subprocess.run(["kill", "-INT", min(rank0, key=int)])
        _, err = p.communicate(timeout=TIMEOUT)
        check(p.returncode == 4, f"SIGINT stops a run on 2 processes with 4 ({p.returncode}: {err[-400:]})")
        check('"status": "interrupted"' in (stopped / "run.json").read_text(), "run.json says interrupted")
        code, err = run(tsubu, launcher, 3, ["resume", str(stopped)])
        check(code == 0, f"it resumes on 3 processes ({code}: {err[-400:]})")
        same_files(alone, stopped, "stopped by SIGINT on 2 processes, resumed on 3")

        # Faults: process 1 killed (SIGKILL) after the first checkpoint ends the job, which
        # resumes from its last good checkpoint; so does the whole job killed at a random time.
        alone_long = tmp / "alone_long"
        code, err = run(tsubu, launcher, 1, ["run", SETTLE, "--out", str(alone_long)] + with_sets(LONG))
        assert code == 0, err
        for name, whole, resumed_on in (("killed1", False, 2), ("killedall", True, 3)):
            out = tmp / name
            p = subprocess.Popen(tsubu_cmd(tsubu, launcher, 2, ["run", SETTLE, "--out", str(out)] + with_sets(LONG)),
                                 stderr=subprocess.PIPE, text=True)
            while not any((out / "checkpoint").glob("step_*.tsbk")):
                time.sleep(0.02)
                assert p.poll() is None, p.stderr.read()
            delay = random.uniform(0.0, MAX_KILL_DELAY) if whole else 0.0
            time.sleep(delay)
            assert p.poll() is None, f"the run ended {delay:.2f} s after its first checkpoint, before the kill: lengthen LONG"
            # Open MPI puts its processes in process groups of their own: each is killed.
            for pid in [process_of(p.pid, 0), process_of(p.pid, 1), p.pid] if whole else [process_of(p.pid, 1)]:
                os.kill(pid, signal.SIGKILL)
            _, err = p.communicate(timeout=TIMEOUT)
            if not whole:
                check(p.returncode != 0 and "rank 1" in err and "signal 9" in err,
                      f"process 1 killed: the job ends, saying so ({p.returncode}: {err[-300:]})")
            code, err = run(tsubu, launcher, resumed_on, ["resume", str(out)])
            check(code == 0, f"{name}: resumes on {resumed_on} processes ({code}: {err[-400:]})")
            same_files(alone_long, out, f"{'the whole job' if whole else 'process 1'} killed ({delay:.2f} s after the first "
                                   f"checkpoint), resumed on {resumed_on}")

        # Rolling resistance (EPSD): its spring, a contact history slot, is handed over and
        # gathered with the others.
        rolling = ["contact.default.rolling=\"epsd\"", "contact.default.rolling_friction=0.1",
                   "contact.default.rolling_damping=0.3", "output.checkpoint_every_steps=1000"]
        for processes in (1, 2):
            code, err = run(tsubu, launcher, processes, ["run", SETTLE, "--out", str(tmp / f"rolling{processes}")] +
                            with_sets(SETS[:1] + rolling))
            assert code == 0, err
        same_files(tmp / "rolling1", tmp / "rolling2", "rolling resistance on 2 processes")
        # The box cut across y ([parallel] counts) rather than along z (the automatic grid).
        code, err = run(tsubu, launcher, 2, ["run", SETTLE, "--out", str(tmp / "rolling_y")] +
                        with_sets(SETS[:1] + rolling + ["parallel.counts=[0, 2, 0]"]))
        assert code == 0, err
        same_files(tmp / "rolling1", tmp / "rolling_y", "rolling resistance on 2 processes cut across y",
                   also_skip={"overrides.txt"})  # the state's record of the --set values: one more here

        # Hindered settling: the solid fraction around a grain counts grains across the cuts.
        hindered = ["fluid.density=1000", "fluid.kinematic_viscosity=1e-6", "fluid.hindered_settling=true"]
        for processes in (1, 2):
            code, err = run(tsubu, launcher, processes, ["run", SETTLE, "--out", str(tmp / f"hindered{processes}")] +
                            with_sets(SETS + hindered))
            assert code == 0, err
        same_files(tmp / "hindered1", tmp / "hindered2", "hindered settling on 2 processes")

        # The inflow: every process admits the same grains; its stream's state is checkpointed.
        # Open faces: grains that leave the chute are counted alike (series.csv, outflow.csv, the
        # checkpoints' totals; outflow.csv cut back to the checkpoint's length on resume). Each
        # on three processes, their newest checkpoint lost, resumed on two.
        for name, scenario, sets, what in [
            ("inflow", INFLOW, ["simulation.duration=0.15", "output.checkpoint_every_steps=2000"], "an inflow"),
            ("chute", CHUTE, ["simulation.duration=0.05", "output.checkpoint_every_steps=1500",
                              "particles.0.lower=[0.02, 0, 0]", "particles.0.upper=[0.04, 0.008, 0.03]"], "a discharge"),
        ]:
            for processes in (1, 3):
                code, err = run(tsubu, launcher, processes, ["run", scenario, "--out", str(tmp / f"{name}{processes}")] +
                                with_sets(sets))
                assert code == 0, err
            checkpoints = sorted((tmp / f"{name}3" / "checkpoint").glob("step_*.tsbk"))
            checkpoints[-1].unlink()
            code, err = run(tsubu, launcher, 2, ["resume", str(tmp / f"{name}3")])
            check(code == 0, f"{what}'s checkpoint of 3 processes resumes on 2 ({code}: {err[-400:]})")
            same_files(tmp / f"{name}1", tmp / f"{name}3", f"{what} on 3 processes, resumed on 2")
        check((tmp / "chute1" / "outflow.csv").read_text().count("\n") > 50, "grains left the chute")
        # Insertion into a bin: every process places the same grains.
        for processes in (1, 2):
            code, err = run(tsubu, launcher, processes, ["run", BIN, "--out", str(tmp / f"bin{processes}")] +
                            with_sets(["simulation.duration=0.12"]))
            assert code == 0, err
        same_files(tmp / "bin1", tmp / "bin2", "insertion into a bin on 2 processes")

        # Moving walls on 3 processes: hand-overs (each a list build) only when a grain has moved
        # half the skin, not every step.
        builds = []
        for processes in (1, 3):
            out = tmp / f"walls{processes}"
            code, err = run(tsubu, launcher, processes, ["run", str(ROOT / "tests/scenarios/contact_network.toml"), "--out",
                                                         str(out), "--set", "simulation.duration=0.05"])
            assert code == 0, err
            builds.append(json.loads((out / "run.json").read_text())["list_builds"])
        check(0 < builds[1] <= 2 * builds[0], f"moving walls: {builds[1]} list builds on process 0 of 3, {builds[0]} alone")

        # Block steps: every process holds the whole run and shares out the active grains. On 3
        # processes with checkpoints, the newest lost, resumed on 2: one process's bytes.
        block = str(ROOT / "tests/scenarios/block_threads.toml")
        block_sets = ["simulation.duration=0.01", "output.checkpoint_every_steps=30", "output.vtk_interval=0.002"]
        for processes in (1, 3):
            code, err = run(tsubu, launcher, processes, ["run", block, "--out", str(tmp / f"block{processes}")] +
                            with_sets(block_sets))
            check(code == 0 and (processes == 1 or "WARNING: block steps on 3 processes: each holds the whole run" in err),
                  f"block steps on {processes} processes, warned of the cost ({code}: {err[-400:]})")
        checkpoints = sorted((tmp / "block3" / "checkpoint").glob("step_*.tsbk"))
        checkpoints[-1].unlink()
        code, err = run(tsubu, launcher, 2, ["resume", str(tmp / "block3")])
        check(code == 0, f"block steps' checkpoint of 3 processes resumes on 2 ({code}: {err[-400:]})")
        same_files(tmp / "block1", tmp / "block3", "block steps on 3 processes, resumed on 2")
        # A grain lost through the top and an overlap beyond the limit: every process fails
        # alike at the same block time; process 0 says it and writes one process's files, the
        # failing state's frame included.
        small = ["run", str(ROOT / "tests/scenarios/valid_small.toml"), "--set", 'simulation.integrator="block_hermite"']
        for name, sets, says in [
            ("lost", ["simulation.gravity=[0, 0, 1000]", "output.checkpoint_every_steps=100", "output.vtk_interval=0.002"],
             "left the domain"),
            ("deep", ["simulation.overlap_limit=1e-3", "output.vtk_interval=0.01"], "overlap"),
        ]:
            outs = [tmp / f"block_{name}{processes}" for processes in (1, 2)]
            codes = [run(tsubu, launcher, processes, small + with_sets(sets) + ["--out", str(out)])
                     for processes, out in zip((1, 2), outs)]
            summaries = [json.loads((out / "run.json").read_text()) for out in outs]
            frames = [sorted(p.name for p in (out / "frames").iterdir()) for out in outs]
            check([c for c, _ in codes] == [3, 3] and "tsubu: process 0: numerical failure: " in codes[1][1]
                  and says in codes[1][1] and summaries[1]["status"] == "failed"
                  and summaries[1]["message"] == summaries[0]["message"].replace(outs[0].name, outs[1].name)
                  and (outs[1] / "series.csv").read_bytes() == (outs[0] / "series.csv").read_bytes()
                  and len(frames[0]) > 2 and frames[0] == frames[1]
                  and all((outs[0] / "frames" / f).read_bytes() == (outs[1] / "frames" / f).read_bytes() for f in frames[0]),
                  f"block steps, {says} on 2 processes: one process's message, series and frames, the failing "
                  f"state's included ({codes[1][0]}: {codes[1][1][-300:]}; {frames})")

        # What a split run refuses, and the one-process commands.
        for scenario, sets, key in [
            ("tests/scenarios/block_threads.toml", ["parallel.counts=[1, 1, 2]"],
             "parallel.counts: block steps share out the active particles among the processes, not the box"),
            ("tests/scenarios/settle_mono.toml", ["parallel.counts=[2, 2, 1]"],
             "parallel.counts: no grid of 2 subdomains (mpirun -np 2) has 2 x 2 x 1"),
        ]:
            out = tmp / "refused"
            code, err = run(tsubu, launcher, 2, ["run", str(ROOT / scenario), "--out", str(out)] + with_sets(sets))
            check(code == 2 and key in err and not out.exists(), f"{key} is refused on 2 processes ({code}: {err[-400:]})")
        code, err = run(tsubu, launcher, 2, ["check", SETTLE])
        check(code == 2 and "`tsubu check` runs as one process" in err, f"check is refused ({code}: {err[-300:]})")
        code, err = run(tsubu, launcher, 2, ["export", str(alone)])
        check(code == 2 and "`tsubu export` runs as one process" in err, f"export is refused ({code}: {err[-300:]})")

        # A grain leaves the box through the top, in process 1's half: the whole job ends with
        # its message, and process 0 records the failure as one process does (run.json, the
        # series up to the failing step, the last good checkpoint named and kept), and writes
        # the failing state's frame, gathered from every process where the drift left them (the
        # step ends there on every process: in its ghosts' refresh, or with an open face in
        # the exchange of the departures).
        lost = ["run", str(ROOT / "tests/scenarios/valid_small.toml"), "--set", "simulation.gravity=[0, 0, 1000]",
                "--set", "output.checkpoint_every_steps=100", "--set", "output.vtk_interval=0.002"]
        for variant, sets in [("", []), ("open", ["--set", 'domain.open=["z_min"]'])]:
            outs = [tmp / f"lost{variant}{processes}" for processes in (1, 2)]
            code1, err1 = run(tsubu, launcher, 1, lost + sets + ["--out", str(outs[0])])
            started = time.monotonic()
            code, err = run(tsubu, launcher, 2, lost + sets + ["--out", str(outs[1])])
            check(code1 == 3 and code == 3 and "tsubu: process 1: numerical failure: " in err and "left the domain" in err,
                  f"a failure on process 1 ends the job with 3 and its message in {time.monotonic() - started:.0f} s "
                  f"({variant}; {code}: {err[-600:]})")
            summaries = [json.loads((out / "run.json").read_text()) for out in outs]
            check(summaries[1]["status"] == "failed"
                  and summaries[1]["message"] == summaries[0]["message"].replace(outs[0].name, outs[1].name)
                  and "checkpoint" in summaries[1]["message"] and summaries[1]["steps"] == summaries[0]["steps"],
                  f"process 0 records process 1's failure in run.json as one process does ({variant}; "
                  f"{summaries[1]['status']}: {summaries[1]['message'][-200:]})")
            check((outs[1] / "series.csv").read_bytes() == (outs[0] / "series.csv").read_bytes()
                  and sorted(p.name for p in (outs[1] / "checkpoint").glob("*.tsbk"))
                  == sorted(p.name for p in (outs[0] / "checkpoint").glob("*.tsbk")) != [],
                  f"the failed split run keeps one process's series and checkpoints ({variant})")
            frames = [sorted(p.name for p in (out / "frames").iterdir()) for out in outs]
            check(len(frames[0]) > 2 and frames[0] == frames[1]
                  and all((outs[0] / "frames" / f).read_bytes() == (outs[1] / "frames" / f).read_bytes() for f in frames[0]),
                  f"a grain lost on process 1 of 2: one process's frames, the failing state's included ({variant}; {frames})")

        # A contact beyond the overlap limit, at a ceiling (process 1's half) and at the floor
        # (process 0's): the failing state is gathered from every process and its frame written,
        # the same files as one process's (the failing frame included).
        deep = ["run", str(ROOT / "tests/scenarios/valid_small.toml"), "--set", "simulation.overlap_limit=1e-3",
                "--set", "output.vtk_interval=0.01"]
        ceiling = ["--set", "walls.0.point=[0, 0, 0.03]", "--set", "walls.0.normal=[0, 0, -1]",
                   "--set", "simulation.gravity=[0, 0, 9.81]"]
        for where, sets, rank in [("a ceiling", ceiling, 1), ("the floor", [], 0)]:
            outs = [tmp / f"deep{processes}-{rank}" for processes in (1, 2)]
            code1, err1 = run(tsubu, launcher, 1, deep + sets + ["--out", str(outs[0])])
            code, err = run(tsubu, launcher, 2, deep + sets + ["--out", str(outs[1])])
            frames = [sorted(p.name for p in (out / "frames").iterdir()) for out in outs]
            check(code1 == 3 and code == 3 and f"tsubu: process {rank}: numerical failure: " in err and "overlap" in err
                  and "frame_00001.vtu" in frames[0] and frames[0] == frames[1]
                  and all((outs[0] / "frames" / f).read_bytes() == (outs[1] / "frames" / f).read_bytes() for f in frames[0]),
                  f"an overlap at {where} on process {rank} of 2: the split run writes one process's frames, the failing "
                  f"state's included ({code}: {err[-300:]}; {frames})")
    if failures:
        sys.exit(f"{len(failures)} failed")


if __name__ == "__main__":
    main()
