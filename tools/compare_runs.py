#!/usr/bin/env python3
"""Runs one set of scenarios with two tsubu executables and compares every output byte for byte.

A refactor must not move a fixed-step or block-step result by one bit. This runs short
versions of scenarios that together cover velocity Verlet, symplectic Euler, block steps,
the inflow (fixed and block steps), hindered settling, walls that move, a turning triangle
mesh, open faces and insertion (fixed and block steps), periodic sides and both contact searches, with each binary, and compares series.csv, track.csv, every frame,
contact network, wall file and .pvd index, the final checkpoint's state (as `tsubu export`
writes it: the checkpoint itself also holds the run id and the wall-clock time) and
run.json's results (its timings and ids are left out). Exit status 0 when everything is identical, 1 otherwise.

    python3 tools/compare_runs.py OLD_TSUBU NEW_TSUBU [--keep DIR] [--threads N] [--new-launcher CMD]

With --new-launcher (a command put before NEW_TSUBU, e.g. "mpirun -np 3"), NEW_TSUBU's runs
are split among processes (docs/parallel.md; block steps share out their active grains),
and run.json's force-evaluation and list-build counters (each process's own work) and its
`processes` (the split's grid and loads) are left out of the comparison.

OLD_TSUBU is, for example, a build of the commit before the change:
    git worktree add /tmp/before HEAD~1 && cmake -S /tmp/before -B /tmp/before/build -G Ninja \
        -DCMAKE_BUILD_TYPE=Release && ninja -C /tmp/before/build tsubu
"""
import argparse
import filecmp
import json
import pathlib
import shlex
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent

# (name, scenario, overrides): each runs a few seconds. Three sort often (search.sort_every), so
# that the renumbering of every per-particle store is exercised.
CASES = [
    ("velocity_verlet", "tests/scenarios/settle_mono.toml", ["simulation.duration=0.05", "search.sort_every=37"]),
    ("symplectic_euler_model_p", "tests/scenarios/checkpoint_model_p.toml", ["simulation.duration=0.02"]),
    ("block_steps", "tests/scenarios/block_sediment.toml", []),
    ("block_steps_inflow", "tests/scenarios/rain_small.toml", ["simulation.duration=0.05", "search.sort_every=3"]),
    # A series row at every step: rows at the steps where grains enter read the contacts'
    # results across the split's arrangement of the new grains.
    ("inflow", "tests/scenarios/inflow_small.toml",
     ["simulation.duration=0.15", "search.sort_every=50", "output.series_interval=2e-5"]),
    ("hindered_settling", "tests/scenarios/sediment_inflow.toml",
     ["simulation.duration=0.03", "simulation.dt=1e-6", "fluid.hindered_settling=true"]),
    ("moving_walls", "tests/scenarios/contact_network.toml", ["simulation.duration=0.05"]),
    ("hysteresis_piston", "examples/piston-hysteresis.toml", ["simulation.duration=0.05"]),
    ("search_multilevel", "tests/scenarios/poly_search.toml", []),
    ("search_cell", "tests/scenarios/poly_search.toml", ['search.method="cell"']),
    ("mesh_walls", "tests/scenarios/mesh_mixer.toml", ["simulation.duration=0.05", "search.sort_every=50"]),
    ("open_faces", "tests/scenarios/chute_open.toml",  # grains leave from the first steps on
     ["simulation.duration=0.05", "search.sort_every=50", "particles.0.lower=[0.02, 0, 0]",
      "particles.0.upper=[0.04, 0.008, 0.03]"]),
    ("insertion", "tests/scenarios/insertion_bin.toml", ["simulation.duration=0.15"]),
]
# Block steps with what the fixed-step cases above add: moving walls, a turning mesh, open
# faces, hindered settling, insertion (run split among processes, they share out their active
# grains: docs/parallel.md).
BLOCK = 'simulation.integrator="block_hermite"'
CASES += [("block_" + name, scenario, sets + [BLOCK]) for name, scenario, sets in CASES
          if name in ("moving_walls", "mesh_walls", "open_faces", "hindered_settling", "insertion")]
# Every case writes frames and a final checkpoint.
COMMON = ["output.vtk_interval=0.01"]
# run.json keys that count the work of the process that writes run.json, in a split run, and
# the split's own description (its grid and what each process held and sent).
COUNTERS = {"particle_force_evaluations", "contact_evaluations", "list_builds", "processes"}
# run.json keys that are measurements of the machine, not results.
UNSTABLE = {"run_id", "wall_time_s", "loop_time_s", "loop_sessions", "particle_steps_per_second", "started",
            "finished", "host", "threads", "tsubu", "version", "sessions", "command"}


def run(tsubu, case, out, threads, launcher=(), may_refuse=False):
    """Runs the case; False when `may_refuse` and the scenario is refused (exit 2: an older
    binary without a feature the case uses)."""
    name, scenario, sets = case
    cmd = [*launcher, tsubu, "run", str(ROOT / scenario), "--out", str(out), "--threads", str(threads)]
    for s in COMMON + sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode == 2 and may_refuse:
        return False
    if r.returncode != 0:
        sys.exit(f"{name}: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    return True


def stable_json(path, leave_out):
    j = json.loads(path.read_text())
    return {k: v for k, v in j.items() if k not in leave_out}


def export(tsubu, run_dir, to):
    """The newest checkpoint's particles and contacts as CSV (full precision): its state,
    without the run id and wall-clock time it also holds."""
    r = subprocess.run([tsubu, "export", str(run_dir), "--to", str(to)], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"tsubu export {run_dir} failed ({r.returncode}):\n{r.stderr}")


def compare(a, b, leave_out):
    """The files that differ between run folders a and b (or exist in one only); run.json
    without the keys `leave_out`."""
    skip = {"run.json", ".tsubu-run", ".tsubu-lock"}
    files_a = {p.relative_to(a) for p in a.rglob("*") if p.is_file() and p.name not in skip and "logs" not in p.parts}
    files_b = {p.relative_to(b) for p in b.rglob("*") if p.is_file() and p.name not in skip and "logs" not in p.parts}
    differ = sorted(str(f) + " (only in one)" for f in files_a ^ files_b)
    for f in sorted(files_a & files_b):
        if f.suffix != ".tsbk" and not filecmp.cmp(a / f, b / f, shallow=False):
            differ.append(str(f))
    if stable_json(a / "run.json", leave_out) != stable_json(b / "run.json", leave_out):
        differ.append("run.json (results)")
    return differ, len(files_a & files_b)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--keep", help="write the runs here (default: a temporary folder, removed)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--new-launcher", default="", help="a command before NEW_TSUBU, e.g. \"mpirun -np 3\"")
    args = ap.parse_args()
    launcher = shlex.split(args.new_launcher)
    leave_out = UNSTABLE | COUNTERS if launcher else UNSTABLE
    with tempfile.TemporaryDirectory() as tmp:
        base = pathlib.Path(args.keep or tmp)
        failed = 0
        for case in CASES:
            a, b = base / case[0] / "old", base / case[0] / "new"
            if not run(args.old, case, a, args.threads, may_refuse=True):
                print(f"{case[0]:26s} skipped: OLD refuses the scenario (a feature it does not have)")
                continue
            run(args.new, case, b, args.threads, launcher)
            export(args.old, a, a / "state")
            export(args.new, b, b / "state")
            differ, n = compare(a, b, leave_out)
            print(f"{case[0]:26s} {n:4d} files " + ("identical" if not differ else "DIFFER: " + ", ".join(differ[:6])))
            failed += bool(differ)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
