#!/usr/bin/env python3
"""The rotating drum of examples/drum/drum.toml side by side with LAMMPS: the same drum
(radius 4 cm, a slice 12 mm long periodic along its axis, turning at 2 rad/s), the same
number of 3 mm glass beads poured in at random, the same contact law as far as LAMMPS has it
(Hertz with Tsuji's dashpot, a Mindlin tangential spring with Coulomb's bound, no rolling
resistance; LAMMPS' input is validation/drum.in, the mapping of each term is in
docs/validation/drum.md), for several seeds in each code. Three sets of runs: tsubu on the
example as it is, with Coulomb's bound on the whole tangential force (`friction_bound =
"total"`), as LAMMPS bounds it; tsubu with the bound on the spring alone and the dashpot on
top (`friction_bound = "spring"`); and LAMMPS. All are measured with the
same estimator, the functions of examples/drum/plot_drum.py: the angle of a frame is the
inclination of the principal axis of the grains' centres across the drum (x, z); a run's
angle is the mean over its frames from 1 s on, with the standard error over blocks of
0.25 s, and a set's angle is the mean over its seeds with the standard error of that mean.
Writes docs/validation/drum.png and drum.csv.

    PYTHONPATH=build/python /usr/bin/python3 validation/drum_lammps.py [--tsubu build/tsubu] [--seeds 1 2 3 4 5]

Runs go to out/validation/drum/ (a finished run is reused): about 20 s for each tsubu run
and 40 s for each LAMMPS run on one core, 7 minutes in all. Without LAMMPS (`lmp` not found)
it says so and exits 0 (Debian: apt-get install lammps).
"""
import argparse
import importlib.util
import json
import math
import os
import shutil
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402
from report_files import save  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENARIO = os.path.join(ROOT, "examples", "drum", "drum.toml")
LAMMPS_INPUT = os.path.join(ROOT, "validation", "drum.in")
SEEDS = (1, 2, 3, 4, 5)
START = 1.0  # s: frames from here on are measured (plot_drum.py's default)
DT = 1e-5  # s, both codes
# The scenario's random source: the box of the centres, the beads' diameter and density.
FILL_LOWER = np.array([-0.025, 0.0, -0.028])
FILL_UPPER = np.array([0.025, 0.012, 0.008])
PERIOD_Y = 0.012
DIAMETER = 0.003
DENSITY = 2500.0
DRUM_RADIUS = 0.04
BOX = ((-0.042, 0.042), (0.0, 0.012), (-0.042, 0.042))
# What is run: tsubu on the example as it is, whose Coulomb bound holds the whole tangential
# force (spring and dashpot), as LAMMPS bounds it; tsubu with the bound on the spring alone
# (friction_bound = "spring", the dashpot on top: the sedimentation paper's law as printed);
# LAMMPS (validation/drum.in). Each is (the runs' folder name, tsubu's --set overrides or None
# for LAMMPS).
CODES = {
    'tsubu (the example, friction_bound = "total")': ("tsubu-total", []),
    'tsubu, friction_bound = "spring"': ("tsubu-spring", ['contact.default.friction_bound="spring"']),
    "LAMMPS": ("lammps", None),
}
COLOURS = dict(zip(CODES, ("tab:green", "tab:blue", "tab:orange")))


def load_plot_drum():
    """examples/drum/plot_drum.py as a module: its surface_angle and mean_and_error are the
    estimator used here for both codes."""
    spec = importlib.util.spec_from_file_location("plot_drum", os.path.join(ROOT, "examples", "drum", "plot_drum.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def finished(folder, marker):
    return os.path.isfile(os.path.join(folder, marker))


def run_tsubu(tsubu, seed, folder, sets=()):
    """One tsubu run of the example with simulation.seed = seed and the overrides `sets`;
    returns its wall time, s."""
    if finished(folder, "wall_seconds"):
        with open(os.path.join(folder, "run.json")) as f:
            if json.load(f).get("status") == "ok":
                with open(os.path.join(folder, "wall_seconds")) as f:
                    return float(f.read())
    start = time.monotonic()
    overrides = [a for v in (f"simulation.seed={seed}", *sets) for a in ("--set", v)]
    subprocess.run([tsubu, "run", SCENARIO, "--out", folder, "--overwrite", "--threads", "1"] + overrides,
                   check=True, stdout=subprocess.DEVNULL)
    seconds = time.monotonic() - start
    with open(os.path.join(folder, "wall_seconds"), "w") as f:
        f.write(f"{seconds:.1f}\n")
    return seconds


def place_grains(n, seed):
    """n centres at random in the fill box, no two closer than a diameter (the y axis
    periodic), by random sequential addition: LAMMPS' initial positions."""
    rng = np.random.default_rng(seed)
    centres = np.empty((0, 3))
    tries = 0
    while len(centres) < n:
        tries += 1
        if tries > 1000 * n:
            sys.exit(f"could not place {n} grains without overlap")
        c = FILL_LOWER + rng.random(3) * (FILL_UPPER - FILL_LOWER)
        d = centres - c
        d[:, 1] -= PERIOD_Y * np.round(d[:, 1] / PERIOD_Y)
        if len(centres) == 0 or np.min(np.einsum("ij,ij->i", d, d)) >= DIAMETER ** 2:
            centres = np.vstack([centres, c])
    return centres


def write_data(path, centres):
    with open(path, "w") as f:
        f.write(f"drum grains (validation/drum_lammps.py)\n\n{len(centres)} atoms\n1 atom types\n\n")
        for (lo, hi), axis in zip(BOX, "xyz"):
            f.write(f"{lo} {hi} {axis}lo {axis}hi\n")
        f.write("\nAtoms # sphere\n\n")
        for i, c in enumerate(centres, 1):
            f.write(f"{i} 1 {DIAMETER} {DENSITY} {c[0]:.9g} {c[1]:.9g} {c[2]:.9g}\n")


def run_lammps(lmp, n, seed, folder):
    """One LAMMPS run of validation/drum.in with n grains placed by `seed`; its wall time, s."""
    if finished(folder, "wall_seconds"):
        with open(os.path.join(folder, "wall_seconds")) as f:
            return float(f.read())
    os.makedirs(folder, exist_ok=True)
    write_data(os.path.join(folder, "grains.data"), place_grains(n, seed))
    start = time.monotonic()
    subprocess.run([lmp, "-in", LAMMPS_INPUT, "-var", "data", "grains.data", "-var", "dump", "dump.drum",
                    "-log", "log.lammps", "-screen", "none"], check=True, cwd=folder)
    seconds = time.monotonic() - start
    with open(os.path.join(folder, "wall_seconds"), "w") as f:
        f.write(f"{seconds:.1f}\n")
    return seconds


class Frame:
    """A frame's centres, diameters and velocities, as tsubu.pictures.draw_grains reads them."""

    def __init__(self, time, points, diameter, velocity):
        self.time, self.points, self._data = time, points, {"diameter": diameter, "velocity": velocity}

    def __getitem__(self, name):
        return self._data[name]


def lammps_frames(folder):
    """The frames of a LAMMPS dump (id x y z vx vy vz diameter, sorted by id)."""
    frames = []
    with open(os.path.join(folder, "dump.drum")) as f:
        lines = f.read().splitlines()
    i = 0
    while i < len(lines):
        step = int(lines[i + 1])
        n = int(lines[i + 3])
        rows = np.array([line.split() for line in lines[i + 9:i + 9 + n]], float)
        frames.append(Frame(step * DT, rows[:, 1:4], rows[:, 7], rows[:, 4:7]))
        i += 9 + n
    return frames


def tsubu_frames(folder):
    from tsubu.runs import read_run
    run = read_run(folder)
    frames = []
    for i, t in enumerate(run.frames.times):
        frame = run.frame(i)
        frames.append(Frame(t, np.asarray(frame.points), np.asarray(frame["diameter"]), np.asarray(frame["velocity"])))
    return frames


def measure(drum, frames):
    """(times, angles, mean angle after START, its block standard error, blocks)."""
    times = np.round([f.time for f in frames], 9)  # LAMMPS' step * dt, to the frames' times
    angles = np.array([drum.surface_angle(f.points)[0] for f in frames])
    steady = times >= START
    mean, error, blocks = drum.mean_and_error(times[steady], angles[steady])
    return times, angles, mean, error, blocks


def seed_mean(values):
    """The mean over seeds and its standard error."""
    values = np.asarray(values, float)
    return float(values.mean()), float(values.std(ddof=1) / math.sqrt(len(values)))


def draw_frame(ax, drum, frame, title):
    from tsubu.pictures import draw_grains
    collection = draw_grains(ax, frame)
    collection.set_clim(0, 0.25)
    angle, centre = drum.surface_angle(frame.points)
    reach = np.ptp(frame.points[:, 0])
    direction = np.array([np.cos(np.radians(angle)), -np.sin(np.radians(angle))])
    line = np.array([centre - 0.6 * reach * direction, centre + 0.6 * reach * direction])
    ax.plot(line[:, 0], line[:, 1], "r-", lw=1.5, label=f"principal axis, {angle:.1f}°")
    ax.add_patch(Circle((0, 0), DRUM_RADIUS, fill=False, color="0.4"))
    ax.set_xlim(*BOX[0])
    ax.set_ylim(*BOX[2])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.legend(loc="upper right", fontsize="small")
    ax.set_title(f"{title}, t = {frame.time:.2f} s", fontsize="medium")
    return collection


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"))
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--seeds", type=int, nargs="+", default=list(SEEDS))
    ap.add_argument("--runs", default=os.path.join(ROOT, "out", "validation", "drum"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "validation"))
    args = ap.parse_args()
    lmp = shutil.which(args.lmp)
    if lmp is None:
        print(f"LAMMPS ({args.lmp}) not found: the drum's comparison is skipped")
        return
    if len(args.seeds) < 2:
        sys.exit("at least two seeds are needed for a standard error over seeds")
    drum = load_plot_drum()
    results = {code: [] for code in CODES}
    for seed in args.seeds:
        grains = None
        for code, (folder_name, sets) in CODES.items():
            folder = os.path.join(args.runs, f"{folder_name}_seed{seed}")
            if sets is None:
                seconds = run_lammps(lmp, grains, seed, folder)
                frames = lammps_frames(folder)
            else:
                seconds = run_tsubu(args.tsubu, seed, folder, sets)
                frames = tsubu_frames(folder)
                grains = grains or len(frames[0].points)
            times, angles, mean, error, blocks = measure(drum, frames)
            results[code].append(dict(seed=seed, grains=len(frames[0].points), wall=seconds, last=frames[-1],
                                      times=times, angles=angles, mean=mean, error=error, blocks=blocks))
            print(f"{code} (seed {seed}): {len(frames[0].points)} grains, {mean:.2f} +- {error:.2f} deg "
                  f"({blocks} blocks of {drum.BLOCK_S} s from {START} s; {seconds:.0f} s of wall time)")

    rows, summary = [], {}
    for code, runs in results.items():
        for r in runs:
            rows.append([code, r["seed"], r["grains"], r["mean"], r["error"], r["blocks"], r["wall"]])
        summary[code] = seed_mean([r["mean"] for r in runs])
        print(f"{code}: {summary[code][0]:.2f} +- {summary[code][1]:.2f} deg (mean over {len(runs)} seeds, "
              f"standard error over seeds)")
        rows.append([code, "mean", "", summary[code][0], summary[code][1], len(runs), ""])
    for code in list(CODES)[:2]:
        difference = summary[code][0] - summary["LAMMPS"][0]
        combined = math.hypot(summary[code][1], summary["LAMMPS"][1])
        print(f"{code} - LAMMPS = {difference:+.2f} +- {combined:.2f} deg ({difference / combined:+.1f} combined "
              f"standard errors)")
        rows.append([f"{code} - LAMMPS", "", "", difference, combined, "", ""])

    fig = plt.figure(figsize=(14, 9))
    grid = fig.add_gridspec(2, 3, height_ratios=[1, 0.9])
    for i, code in enumerate(CODES):
        ax = fig.add_subplot(grid[0, i])
        collection = draw_frame(ax, drum, results[code][0]["last"], f"{code}, seed {results[code][0]['seed']}")
        fig.colorbar(collection, ax=ax, label="speed (m/s)", shrink=0.7)
    ax = fig.add_subplot(grid[1, :])
    for code, runs in results.items():
        for k, r in enumerate(runs):
            ax.plot(r["times"], r["angles"], color=COLOURS[code], lw=0.8, alpha=0.6,
                    label=f"{code}, {len(runs)} seeds" if k == 0 else None)
        mean, error = summary[code]
        ax.axhspan(mean - error, mean + error, color=COLOURS[code], alpha=0.25)
        ax.axhline(mean, color=COLOURS[code], lw=1.5, ls="--", label=f"{mean:.1f} ± {error:.1f}° (1-3 s)")
    ax.axvspan(START, max(r["times"][-1] for r in results["LAMMPS"]), color="0.5", alpha=0.06)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("dynamic angle of repose (°)")
    ax.legend(fontsize="small", loc="lower right", ncol=3)
    ax.grid(alpha=0.3)
    fig.suptitle("Rotating drum (examples/drum/drum.toml): tsubu and LAMMPS on the same set-up")
    os.makedirs(args.out, exist_ok=True)
    save(fig, args.out, "drum", ["code", "seed", "grains", "angle_deg", "standard_error_deg", "blocks_or_seeds",
                                 "wall_seconds"], rows)
    print(f"wrote {os.path.join(args.out, 'drum.png')} and drum.csv")


if __name__ == "__main__":
    main()
