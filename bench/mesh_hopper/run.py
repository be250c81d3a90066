#!/usr/bin/env python3
"""A mesh-heavy benchmark against LIGGGHTS: the square hopper (examples/hopper/square_hopper.toml,
576 triangles) discharging from a settled bed, one core and one thread in each code.

1. The bed: tsubu runs the example to t = 0.4 s (the beads settled on the plug) and exports its
   particles (`tsubu run`, `tsubu export`); the same state becomes a LIGGGHTS data file
   (positions, diameters, velocities and spins; contact histories start empty in both).
2. The timing: STEPS steps of the discharge (no plug) from that bed, discharge.toml in tsubu
   (`--threads 1`, OMP_NUM_THREADS=1) and discharge_liggghts.in in LIGGGHTS (serial, no
   mpirun), PAIRS pairs of runs alternating (the order swapped every other pair, so that a
   drift of the machine's speed falls on both). Each code's own loop timer: run.json
   `loop_time_s` and LIGGGHTS' "Loop time". Particle-steps/s = (beads present, averaged over
   the window) x steps / loop time; the ratio tsubu/LIGGGHTS pair by pair, its median and
   spread (min-max).
3. The physics: the mass discharged in the window by each code (both codes are deterministic
   on one thread: every pair gives the same). With --physics-steps N, one longer run of each
   (and of tsubu with the `linear_coulomb` tangential law, LIGGGHTS' own) gives the discharged
   mass and the steady discharge rate, fitted from t = 0.1 s on.

usage: bench/mesh_hopper/run.py [--tsubu BIN] [--pairs 5] [--steps 20000] [--work DIR]
                                [--physics-steps 0] [--skin 3e-4]
The tsubu binary: --tsubu, else $TSUBU, else build/tsubu. Without `liggghts` on the PATH the
LIGGGHTS runs are skipped with a message (apt-get install liggghts). Everything the script
reads is in the repository or written by it into --work (default out/mesh_hopper).
"""
import argparse
import csv
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
example = os.path.join(root, "examples", "hopper", "square_hopper.toml")
mesh = os.path.join(root, "examples", "hopper", "square_hopper.stl")
scenario = os.path.join(here, "discharge.toml")
lig_input = os.path.join(here, "discharge_liggghts.in")

DT = 1e-5
DENSITY = 2500.0
BOX = ((-0.032, 0.032), (-0.032, 0.032), (-0.02, 0.16))
BED_TIME = 0.4       # the plug's time in the example
SAMPLE_STEPS = 500   # series.csv every 0.005 s; LIGGGHTS' thermo every 500 steps


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def one_thread_env():
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    return env


def run(cmd, log):
    with open(log, "w") as out:
        r = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=one_thread_env())
    if r.returncode != 0:
        sys.exit(f"run.py: {' '.join(cmd)} exited {r.returncode}; see {log}")


def prepare_bed(tsubu, work):
    """The example's bed at t = 0.4 s: a tsubu export (particles CSV) and a LIGGGHTS data file."""
    bed_dir = os.path.join(work, "bed")
    export = os.path.join(bed_dir, "export")
    csvs = sorted(f for f in os.listdir(export) if f.startswith("particles_")) if os.path.isdir(export) else []
    if not csvs:
        print(f"bed: {example} to t = {BED_TIME} s ...", flush=True)
        run([tsubu, "run", example, "--out", bed_dir, "--overwrite", "--threads", "1",
             "--set", f"simulation.duration={BED_TIME}", "--set", "output.vtk_interval=0"],
            os.path.join(work, "bed.log"))
        run([tsubu, "export", bed_dir, "--to", export], os.path.join(work, "export.log"))
        csvs = sorted(f for f in os.listdir(export) if f.startswith("particles_"))
    bed_csv = os.path.join(export, csvs[-1])
    with open(bed_csv) as f:
        rows = list(csv.reader(f))[1:]
    # columns: id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz
    data = os.path.join(work, "bed.data")
    with open(data, "w") as f:
        f.write(f"square hopper bed (from {os.path.basename(bed_csv)})\n\n{len(rows)} atoms\n1 atom types\n\n")
        for (lo, hi), a in zip(BOX, "xyz"):
            f.write(f"{lo!r} {hi!r} {a}lo {a}hi\n")
        f.write("\nAtoms\n\n")
        for i, r in enumerate(rows, 1):
            f.write(f"{i} 1 {2 * float(r[2])!r} {DENSITY!r} {r[3]} {r[4]} {r[5]}\n")
        f.write("\nVelocities\n\n")
        for i, r in enumerate(rows, 1):
            f.write(f"{i} {' '.join(r[6:12])}\n")
    masses = [DENSITY * math.pi / 6 * (2 * float(r[2])) ** 3 for r in rows]
    return bed_csv, data, len(rows), masses


def mean_count(times_counts, t_end):
    """Beads present averaged over [0, t_end] (trapezoids over the samples)."""
    area = 0.0
    for (t0, n0), (t1, n1) in zip(times_counts, times_counts[1:]):
        area += 0.5 * (n0 + n1) * (t1 - t0)
    return area / t_end


def steady_rate(times_masses, t_from=0.1):
    """Least-squares slope of the discharged mass over time from t_from on, kg/s."""
    pts = [(t, m) for t, m in times_masses if t >= t_from - 1e-12]
    if len(pts) < 3:
        return float("nan")
    tm = statistics.fmean(t for t, _ in pts)
    mm = statistics.fmean(m for _, m in pts)
    return sum((t - tm) * (m - mm) for t, m in pts) / sum((t - tm) ** 2 for t, _ in pts)


def run_tsubu(tsubu, work, tag, bed_csv, n0, steps, scenario_file=scenario):
    out = os.path.join(work, tag)
    load = loadavg()
    run([tsubu, "run", scenario_file, "--out", out, "--overwrite", "--threads", "1",
         "--set", f"particles.0.file=\"{bed_csv}\"", "--set", f"simulation.duration={steps * DT!r}",
         "--set", f"output.series_interval={SAMPLE_STEPS * DT!r}"],
        os.path.join(work, tag + ".log"))
    with open(os.path.join(out, "run.json")) as f:
        meta = json.load(f)
    series = []
    with open(os.path.join(out, "series.csv")) as f:
        for row in csv.DictReader(f):
            series.append((float(row["time"]), n0 - int(row["outflow_count"]), float(row["outflow_mass"])))
    t_end = meta["steps"] * DT
    n_mean = mean_count([(t, n) for t, n, _ in series], t_end)
    loop = meta["loop_time_s"]
    return {"code": "tsubu", "loop_s": loop, "steps": meta["steps"], "mean_beads": n_mean,
            "rate": n_mean * meta["steps"] / loop, "discharged_kg": series[-1][2],
            "end_beads": series[-1][1], "steady_kg_s": steady_rate([(t, m) for t, _, m in series]),
            "load": load}


def run_liggghts(work, tag, data, n0, masses, steps, skin):
    screen = os.path.join(work, tag + ".out")
    load = loadavg()
    run(["liggghts", "-in", lig_input, "-var", "data", data, "-var", "mesh", mesh,
         "-var", "nsteps", str(steps), "-var", "dt", repr(DT), "-var", "skin", repr(skin),
         "-var", "thermo", str(SAMPLE_STEPS), "-log", "none", "-screen", screen],
        os.path.join(work, tag + ".log"))
    counts, loop, loop_steps = [], None, None
    with open(screen) as f:
        in_thermo = False
        for line in f:
            w = line.split()
            if w[:2] == ["Step", "Atoms"]:
                in_thermo = True
                continue
            if line.startswith("Loop time of"):
                loop, loop_steps = float(w[3]), int(w[8])
                in_thermo = False
                continue
            if in_thermo and len(w) >= 2 and w[0].isdigit():
                counts.append((int(w[0]) * DT, int(w[1])))
    if loop is None:
        sys.exit(f"run.py: no 'Loop time' in {screen}")
    # all beads have one mass here; the discharged mass is the beads lost times it
    m = statistics.fmean(masses)
    n_mean = mean_count(counts, loop_steps * DT)
    return {"code": "liggghts", "loop_s": loop, "steps": loop_steps, "mean_beads": n_mean,
            "rate": n_mean * loop_steps / loop, "discharged_kg": (n0 - counts[-1][1]) * m,
            "end_beads": counts[-1][1],
            "steady_kg_s": steady_rate([(t, (n0 - n) * m) for t, n in counts]), "load": load}


def linear_coulomb_variant(work):
    """discharge.toml with LIGGGHTS' tangential law (tsubu `linear_coulomb`), in the work folder."""
    with open(scenario) as f:
        text = f.read()
    text = text.replace('tangential = "mindlin"', 'tangential = "linear_coulomb"')
    text = "\n".join(l for l in text.splitlines() if not l.startswith("friction_bound")) + "\n"
    text = text.replace('file = "../../examples/hopper/square_hopper.stl"', f'file = "{mesh}"')
    path = os.path.join(work, "discharge_linear_coulomb.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tsubu", default=os.environ.get("TSUBU", os.path.join(root, "build", "tsubu")))
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--skin", type=float, default=3e-4,
                    help="LIGGGHTS' neighbour skin, m (tsubu's default: a tenth of the smallest diameter, 0.3 mm)")
    ap.add_argument("--physics-steps", type=int, default=0,
                    help="one longer run of each code for the physics check (0: none)")
    ap.add_argument("--work", default=os.path.join(root, "out", "mesh_hopper"))
    a = ap.parse_args()
    tsubu = os.path.abspath(a.tsubu)
    if not os.access(tsubu, os.X_OK):
        sys.exit(f"run.py: no tsubu binary at {tsubu} (build it, or give --tsubu or TSUBU)")
    have_lig = shutil.which("liggghts") is not None
    if not have_lig:
        print("run.py: `liggghts` is not on the PATH (Debian: apt-get install liggghts): "
              "the LIGGGHTS runs are skipped, tsubu's alone are timed")
    work = os.path.abspath(a.work)
    os.makedirs(work, exist_ok=True)
    bed_csv, data, n0, masses = prepare_bed(tsubu, work)
    print(f"bed: {n0} beads, {sum(masses) * 1e3:.2f} g ({bed_csv})")
    print(f"timing: {a.steps} steps (dt = {DT} s), {a.pairs} pairs, one thread each; "
          f"load before: {loadavg()}", flush=True)

    samples = []
    header = f"{'pair':>4} {'code':>8} {'loop s':>8} {'beads':>7} {'p-steps/s':>10} {'out g':>7} {'load (1, 5, 15 min)':>20}"
    print(header)
    ratios = []
    for p in range(1, a.pairs + 1):
        order = ["tsubu", "liggghts"] if p % 2 else ["liggghts", "tsubu"]
        got = {}
        for code in order:
            if code == "tsubu":
                r = run_tsubu(tsubu, work, f"tsubu_{p}", bed_csv, n0, a.steps)
            elif have_lig:
                r = run_liggghts(work, f"liggghts_{p}", data, n0, masses, a.steps, a.skin)
            else:
                continue
            r["pair"] = p
            got[code] = r
            samples.append(r)
            print(f"{p:>4} {code:>8} {r['loop_s']:8.2f} {r['mean_beads']:7.0f} {r['rate']:10.3e} "
                  f"{r['discharged_kg'] * 1e3:7.2f} {r['load']:>20}", flush=True)
        if "liggghts" in got:
            ratios.append(got["tsubu"]["rate"] / got["liggghts"]["rate"])
            print(f"{p:>4} {'ratio':>8} tsubu/LIGGGHTS = {ratios[-1]:.3f}", flush=True)

    with open(os.path.join(work, "samples.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["pair", "code", "steps", "loop_s", "mean_beads", "particle_steps_per_s",
                    "discharged_kg", "end_beads", "load"])
        for r in samples:
            w.writerow([r["pair"], r["code"], r["steps"], r["loop_s"], r["mean_beads"], r["rate"],
                        r["discharged_kg"], r["end_beads"], r["load"]])

    print(f"\nload after: {loadavg()}")
    for code in ("tsubu", "liggghts"):
        rs = [r for r in samples if r["code"] == code]
        if rs:
            v = [r["rate"] for r in rs]
            print(f"{code:>8}: particle-steps/s median {statistics.median(v):.3e} "
                  f"(min {min(v):.3e}, max {max(v):.3e}); discharged in {a.steps} steps: "
                  f"{rs[0]['discharged_kg'] * 1e3:.2f} g ({n0 - rs[0]['end_beads']} beads)")
    if ratios:
        print(f"ratio tsubu/LIGGGHTS: median {statistics.median(ratios):.3f}, "
              f"spread {min(ratios):.3f}-{max(ratios):.3f} over {len(ratios)} pairs")
        t = [r for r in samples if r["code"] == "tsubu"][0]["discharged_kg"]
        l = [r for r in samples if r["code"] == "liggghts"][0]["discharged_kg"]
        if l > 0:
            print(f"discharged mass tsubu/LIGGGHTS: {t / l:.3f} ({(t - l) / l * 100:+.1f} %)")

    if a.physics_steps > 0:
        print(f"\nphysics: one run of each, {a.physics_steps} steps ({a.physics_steps * DT:g} s)", flush=True)
        runs = [("tsubu (mindlin)", lambda: run_tsubu(tsubu, work, "physics_tsubu", bed_csv, n0, a.physics_steps)),
                ("tsubu (linear_coulomb)", lambda: run_tsubu(tsubu, work, "physics_tsubu_lc", bed_csv, n0,
                                                             a.physics_steps, linear_coulomb_variant(work)))]
        if have_lig:
            runs.append(("liggghts", lambda: run_liggghts(work, "physics_liggghts", data, n0, masses,
                                                          a.physics_steps, a.skin)))
        for name, go in runs:
            r = go()
            print(f"{name:>24}: discharged {r['discharged_kg'] * 1e3:7.2f} g ({n0 - r['end_beads']} beads), "
                  f"steady rate from t = 0.1 s {r['steady_kg_s'] * 1e3:6.2f} g/s, "
                  f"{r['rate']:.3e} particle-steps/s (load {r['load']})", flush=True)


if __name__ == "__main__":
    main()
