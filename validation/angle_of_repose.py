#!/usr/bin/env python3
"""Angle of repose against rolling friction: runs examples/rolling/collapse.toml (a column of
glass beads slumping into a heap once its gate slides away) for several coefficients mu_r
under both rolling models and three seeds, measures the slope of each heap at rest, and writes
docs/validation/angle-of-repose.png and angle-of-repose.csv.

    /usr/bin/python3 validation/angle_of_repose.py [--tsubu build/tsubu] [--out docs/validation] [--jobs 1]

The slope: the heap's free surface is the top (z + r) of the highest bead in each column of
width d_max along x, and the angle is that of the least-squares line through the columns
whose top lies between 20 % and 80 % of the highest (the part that slid, without the flat
remains of the column's top or the single layer of beads that rolled out along the floor).
Each (model, mu_r) is the mean over the seeds with the standard error of that mean.
"""
import argparse
import concurrent.futures
import csv
import glob
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from report_files import save  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENARIO = os.path.join(ROOT, "examples", "rolling", "collapse.toml")
D_MAX = 0.0045  # m: the scenario's largest bead
MODELS = ("epsd", "cdt")
MU_R = (0.0, 0.05, 0.1, 0.2, 0.4)
SEEDS = (1, 2, 3)
BAND = (0.2, 0.8)  # the part of the heap's height whose surface is fitted


def scenario_of(model, folder):
    """The scenario file of a rolling model: the example (epsd) or its text for cdt, which
    has no dashpot (its key rolling_damping is refused with cdt)."""
    if model == "epsd":
        return SCENARIO
    with open(SCENARIO) as f:
        text = f.read().replace('rolling = "epsd"', f'rolling = "{model}"')
    path = os.path.join(folder, f"collapse-{model}.toml")
    with open(path, "w") as f:
        f.write("".join(line for line in text.splitlines(keepends=True) if not line.startswith("rolling_damping")))
    return path


def run(tsubu, model, mu_r, seed, folder):
    """Runs one heap and returns (angle in degrees, stop reason, simulated time in s)."""
    os.makedirs(folder)
    subprocess.run([tsubu, "run", scenario_of(model, folder), "--out", os.path.join(folder, "run"), "--threads", "1",
                    "--set", f"contact.default.rolling_friction={mu_r}", "--set", f"simulation.seed={seed}"],
                   check=True, stdout=subprocess.DEVNULL)
    folder = os.path.join(folder, "run")
    subprocess.run([tsubu, "export", folder], check=True, stdout=subprocess.DEVNULL)
    (particles,) = glob.glob(os.path.join(folder, "export", "particles_*.csv"))
    with open(os.path.join(folder, "run.json")) as f:
        info = json.load(f)
    return heap_angle(particles), info["stop_reason"], info["steps"] * info["dt"]


def surface(particles_csv):
    """[(x, top)] of the heap: the highest bead top in each column of width D_MAX."""
    tops = {}
    with open(particles_csv) as f:
        for r in csv.DictReader(f):
            k = int(float(r["x[m]"]) // D_MAX)
            tops[k] = max(tops.get(k, 0.0), float(r["z[m]"]) + float(r["radius[m]"]))
    return [((k + 0.5) * D_MAX, tops[k]) for k in sorted(tops)]


def heap_angle(particles_csv):
    """The slope of the heap's surface between BAND of its height, in degrees."""
    profile = surface(particles_csv)
    top = max(h for _, h in profile)
    points = [(x, h) for x, h in profile if BAND[0] * top <= h <= BAND[1] * top]
    n = len(points)
    sx, sh = sum(x for x, _ in points), sum(h for _, h in points)
    sxx, sxh = sum(x * x for x, _ in points), sum(x * h for x, h in points)
    slope = (n * sxh - sx * sh) / (n * sxx - sx * sx)
    return math.degrees(math.atan(-slope))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "validation"))
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time")
    opts = ap.parse_args()
    cases = [(model, mu_r, seed) for model in MODELS for mu_r in MU_R for seed in SEEDS]
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(opts.jobs) as pool:
        futures = {case: pool.submit(run, opts.tsubu, *case, os.path.join(tmp, "-".join(map(str, case))))
                   for case in cases}
        results = {}
        for case, f in futures.items():
            results[case] = f.result()
            print(f"{case[0]} mu_r = {case[1]} seed {case[2]}: {results[case][0]:.2f} deg, {results[case][1]}", flush=True)
    rows = []
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for k, model in enumerate(MODELS):
        means, errors = [], []
        for mu_r in MU_R:
            angles = [results[(model, mu_r, seed)][0] for seed in SEEDS]
            mean, error = statistics.mean(angles), statistics.stdev(angles) / math.sqrt(len(angles))
            means.append(mean), errors.append(error)
            for seed, (angle, reason, t) in zip(SEEDS, (results[(model, mu_r, s)] for s in SEEDS)):
                rows.append([model, mu_r, seed, f"{angle:.2f}", f"{t:.3f}", reason])
            print(f"{model} mu_r = {mu_r}: {mean:.1f} +- {error:.1f} deg (seeds: {', '.join(f'{a:.1f}' for a in angles)})")
        ax.errorbar([m + 0.004 * (k - 0.5) for m in MU_R], means, yerr=errors, marker="os"[k], capsize=3,
                    label=f"tsubu, {model}")
    ax.set_xlabel("rolling friction μ_r")
    ax.set_ylabel("slope of the heap at rest (degrees)")
    ax.set_title("A collapsed column of glass beads (sliding friction 0.5)")
    ax.legend()
    save(fig, opts.out, "angle-of-repose", ["model", "mu_r", "seed", "angle_deg", "time_at_rest_s", "stop_reason"], rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
