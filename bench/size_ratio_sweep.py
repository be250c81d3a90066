#!/usr/bin/python3
"""Whole-step cost per particle-step against the grain-size ratio, single grid vs multi-level grid.

For each size ratio d_max/d_min (1, 2, 5, 10, 20, 50; d_min = 0.5 mm) the engine's random source
places a loose bed of about --particles grains at solid fraction 0.3, number density n(d) ∝ d^-2
(Talbot exponent 1; one size at ratio 1), in a cube periodic in x and y with a floor at z = 0.
The grains then get Gaussian random velocities so that they collide and the neighbour lists are
rebuilt: --sigma per component for d_min, sigma (d_min/d)^1.5 for d, the same mean kinetic energy
for every size (with one sigma for all sizes, as the shared bed poly10-gas-vrand, large grains
crush small ones beyond the overlap limit from ratio 10). The random source can only give every
grain the same velocity, so the placed bed is read back from its first VTK frame and run from a
CSV file. Physics of the bench beds: Hertz-Tsuji normal, Mindlin
tangential, e 0.5, mu 0.5, E 5e7, nu 0.3, density 2500, gravity; dt = t_c/20 of the smallest
equal pair at 1 m/s, rounded down, the same for every ratio.

Each ratio runs --steps steps with [search] method = "cell" and "multilevel" (automatic levels),
one thread, alternating, --repeat times; the median of run.json's particle_steps_per_second
(grains x steps / time of the stepping loop) is kept, and run.json's list_builds. Writes
OUT/size_ratio.{csv,md,png}. Needs Debian's /usr/bin/python3 (numpy, matplotlib).

  /usr/bin/python3 bench/size_ratio_sweep.py [--tsubu build/tsubu] [--particles 20000] [--steps 1000]
      [--repeat 3] [--sigma 0.5] [--out bench/results]
  /usr/bin/python3 bench/size_ratio_sweep.py --particles 2000 --steps 100 --repeat 1 --out /tmp/sweep-smoke
"""
import argparse
import base64
import csv
import datetime
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RATIOS = [1, 2, 5, 10, 20, 50]
METHODS = ["cell", "multilevel"]
D_MIN, PHI = 0.5e-3, 0.3
DENSITY, YOUNG, POISSON = 2500.0, 5e7, 0.3


def time_step():
    """t_c/20 of two equal grains of d_min meeting at 1 m/s, rounded down to 1, 1.25, 2, 2.5 or 5 x 10^k."""
    m_eff = DENSITY * math.pi / 6 * D_MIN**3 / 2
    r_eff = D_MIN / 4
    e_eff = YOUNG / (2 * (1 - POISSON**2))
    speed = 1.0
    t_c = 2.868 * (m_eff**2 / (r_eff * e_eff**2 * speed)) ** 0.2
    exponent = math.floor(math.log10(t_c / 20))
    return max(dt for dt in (float(f"{m}e{exponent}") for m in (1, 1.25, 2, 2.5, 5)) if dt <= t_c / 20)


def box_side(ratio, particles):
    """Edge of the cube holding `particles` grains at solid fraction PHI."""
    d_max = ratio * D_MIN
    mean_d3 = D_MIN**3 if ratio == 1 else 0.5 * (d_max**2 - D_MIN**2) / (1 / D_MIN - 1 / d_max)
    return (particles * math.pi / 6 * mean_d3 / PHI) ** (1 / 3)


def scenario(ratio, side, top, dt, steps, particles, frames):
    """Scenario text; `particles` is the [[particles]] table, `frames` writes a VTK frame every step."""
    duration = steps * dt
    return f"""[simulation]
duration = {duration!r}
dt = {dt!r}
gravity = [0, 0, -9.81]
seed = {40 + ratio}

[domain]
lower = [0, 0, 0]
upper = [{side!r}, {side!r}, {top!r}]
periodic = ["x", "y"]

[[materials]]
name = "grain"
density = {DENSITY}
youngs_modulus = {YOUNG}
poisson = {POISSON}

[contact.default]
normal = "hertz_tsuji"
tangential = "mindlin"
restitution = 0.5
friction = 0.5

[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
material = "grain"

[[particles]]
material = "grain"
{particles}
[output]
vtk_interval = {dt if frames else 0!r}
series_interval = {duration!r}
checkpoint_every_steps = 0
checkpoint_every_seconds = 0
"""


def tsubu(binary, args, what):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.run([binary, *args], env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"size_ratio_sweep: {what} failed (tsubu exit code {proc.returncode}):\n"
                 f"  {binary} {' '.join(args)}\n{proc.stderr.strip()}")
    return proc


def read_vtu(path):
    """Positions and diameters of a frame (inline binary arrays: base64 of a UInt64 size, then of the data)."""
    with open(path) as f:
        text = f.read()

    def array(name):
        b64 = re.search(rf'Name="{name}"[^>]*>([^<]*)<', text).group(1)
        return np.frombuffer(base64.b64decode(b64[12:]), dtype="<f8")
    return array("position").reshape(-1, 3), array("diameter")


def prepare(binary, ratio, args, dt, work):
    """Place the bed of one ratio, give it random velocities; return the path of the timed scenario."""
    side = box_side(ratio, args.particles)
    d_max = ratio * D_MIN
    # Room above the bed for grains thrown up: 6 sigma over the run, and a largest grain.
    top = side + d_max + 6 * args.sigma * args.steps * dt
    dist = (f'{{ type = "single", diameter = {D_MIN!r} }}' if ratio == 1 else
            f'{{ type = "talbot", d_min = {D_MIN!r}, d_max = {d_max!r}, exponent = 1 }}')
    random_source = (f'source = "random"\nlower = [0, 0, 0]\nupper = [{side!r}, {side!r}, {side!r}]\n'
                     f"solid_fraction = {PHI}\ndistribution = {dist}\n")
    place = os.path.join(work, f"place-{ratio}.toml")
    with open(place, "w") as f:
        f.write(scenario(ratio, side, top, dt, 1, random_source, frames=True))
    tsubu(binary, ["run", place, "--out", os.path.join(work, f"place-{ratio}")], f"placing the bed of ratio {ratio}")
    position, diameter = read_vtu(os.path.join(work, f"place-{ratio}", "frames", "frame_00000.vtu"))
    spread = args.sigma * (D_MIN / diameter) ** 1.5  # equal mean kinetic energy for every size
    velocity = np.random.default_rng(ratio).normal(0.0, 1.0, position.shape) * spread[:, None]
    bed = os.path.join(work, f"bed-{ratio}.csv")
    np.savetxt(bed, np.column_stack([position, diameter, velocity]), fmt="%.17g", delimiter=",",
               header="x,y,z,d,vx,vy,vz", comments="")
    timed = os.path.join(work, f"ratio-{ratio}.toml")
    with open(timed, "w") as f:
        csv_source = f'source = "csv"\nfile = "{bed}"\noverlap_tolerance = 1e-6\n'
        f.write(scenario(ratio, side, top, dt, args.steps, csv_source, frames=False))
    for method in METHODS:
        tsubu(binary, ["check", timed, "--set", f'search.method="{method}"'], f"checking {timed} with method {method}")
    return timed


def run(binary, timed, method, out, extra=()):
    # --overwrite: every timed run replaces the previous one in the same folder.
    tsubu(binary, ["run", timed, "--out", out, "--overwrite", "--threads", "1", "--set", f'search.method="{method}"', *extra],
          f"running {timed} with method {method}")
    with open(os.path.join(out, "run.json")) as f:
        report = json.load(f)
    if report["status"] != "ok":
        sys.exit(f"size_ratio_sweep: {timed} with method {method}: status {report['status']}: {report['message']}")
    return report


def cpu_model():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown CPU"


def write_results(rows, args, dt, out):
    base = {m: rows[0][f"ns_{m}"] for m in METHODS}
    for r in rows:
        for m in METHODS:
            r[f"{m}_vs_ratio1"] = round(r[f"ns_{m}"] / base[m], 3)
    with open(os.path.join(out, "size_ratio.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    ratios = [r["ratio"] for r in rows]
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    ax.plot(ratios, [r["ns_cell"] for r in rows], "o-", label="cell grid (one level)")
    ax.plot(ratios, [r["ns_multilevel"] for r in rows], "s-", label="multi-level grid (automatic levels)")
    ax.axhline(2 * base["multilevel"], color="gray", ls="--", label="target: 2x multi-level at ratio 1")
    ax.set_xscale("log")
    ax.set_xticks(ratios, [str(r) for r in ratios])
    ax.set_xlabel("size ratio d_max / d_min")
    ax.set_ylabel("ns per particle-step (one thread)")
    ax.set_title(f"~{args.particles:,} grains, solid fraction {PHI}, n(d) ∝ d^-2, {args.steps} steps", fontsize=10)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "size_ratio.png"), dpi=120)

    last = rows[-1]
    verdict = last["multilevel_vs_ratio1"]
    lines = [
        "# Whole time step against the grain-size ratio: cell grid vs multi-level grid", "",
        f"{datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')}, {cpu_model()}, "
        f"{os.cpu_count()} cores, one thread (OMP_NUM_THREADS=1, --threads 1), median of {args.repeat} "
        f"alternating runs per method: bench/size_ratio_sweep.py --particles {args.particles} --steps {args.steps} "
        f"--repeat {args.repeat} --sigma {args.sigma:g}.", "",
        f"Bed: the engine's random source places ~{args.particles:,} grains at solid fraction {PHI} in a cube "
        f"(n(d) ∝ d^-2 between d_min = {D_MIN * 1e3:g} mm and ratio x d_min; one size at ratio 1), periodic in x "
        "and y, floor at z = 0; every grain then gets a Gaussian random velocity, per component "
        f"{args.sigma:g} m/s x (d_min/d)^1.5 (the same mean kinetic energy for every size; run from a CSV file, "
        "as the random source gives all grains one velocity). Hertz-Tsuji normal, Mindlin tangential, e 0.5, "
        "mu 0.5, E 5e7 Pa, nu 0.3, density 2500, "
        f"gravity; dt = {dt:g} s (t_c/20 of two d_min grains at 1 m/s, rounded down) for every ratio; skin a "
        f"tenth of d_min; {args.steps} steps.", "",
        "Time: run.json's particle_steps_per_second, grains x steps / time of the stepping loop (without "
        "set-up and the first force evaluation, like the peers' Loop time; two series.csv rows are in it); "
        "loading, placing and reading the particles and the final analyses are outside it. Contacts: "
        "touching contacts (pairs and floor) per grain, averaged over the steps (run.json contact_evaluations "
        "/ (N steps)). Builds: neighbour-list builds in the run, the first included (run.json list_builds; the "
        "same for both methods, which give the same bits).", "",
        "| size ratio | particles | cell ns/particle-step | multi-level ns/particle-step | cell / ratio 1 | "
        "multi-level / ratio 1 | contacts/particle | list builds |",
        "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['ratio']} | {r['particles']} | {r['ns_cell']:.0f} | {r['ns_multilevel']:.0f} | "
                     f"{r['cell_vs_ratio1']:.2f} | {r['multilevel_vs_ratio1']:.2f} | "
                     f"{r['contacts_per_particle']:.3f} | {r['list_builds']} |")
    lines += ["", f"Verdict: the multi-level grid's cost per particle-step at ratio {last['ratio']} is "
              f"{verdict:.2f}x its cost at ratio 1, {'within' if verdict <= 2 else 'beyond'} the 2x target "
              f"(the cell grid: {last['cell_vs_ratio1']:.2f}x)."]
    with open(os.path.join(out, "size_ratio.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"), help="tsubu binary")
    p.add_argument("--particles", type=int, default=20000, help="grains per bed (about)")
    p.add_argument("--steps", type=int, default=1000, help="steps per run")
    p.add_argument("--repeat", type=int, default=3, help="timed runs per method and ratio (median)")
    p.add_argument("--sigma", type=float, default=0.5, help="random velocity per component of d_min grains, m/s")
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"), help="folder for size_ratio.*")
    args = p.parse_args()
    if args.repeat < 1:
        p.error("--repeat must be at least 1")
    os.makedirs(args.out, exist_ok=True)
    dt = time_step()
    samples = {(r, m): [] for r in RATIOS for m in METHODS}
    with tempfile.TemporaryDirectory(prefix="tsubu-size-ratio-") as work:
        beds = {}
        for ratio in RATIOS:
            beds[ratio] = prepare(args.tsubu, ratio, args, dt, work)
        reports = {}
        for rep in range(args.repeat):
            for i, ratio in enumerate(RATIOS):
                order = METHODS if (rep + i) % 2 == 0 else METHODS[::-1]
                for method in order:
                    report = run(args.tsubu, beds[ratio], method, os.path.join(work, "run"))
                    samples[(ratio, method)].append(1e9 / report["particle_steps_per_second"])
                    reports[ratio] = report
                print(f"round {rep + 1}, ratio {ratio}: " + ", ".join(
                    f"{m} {samples[(ratio, m)][-1]:.0f} ns" for m in METHODS), file=sys.stderr)
    rows = []
    for ratio in RATIOS:
        report = reports[ratio]
        n = report["particles"]
        rows.append({"ratio": ratio, "particles": n, "steps": report["steps"], "dt": report["dt"],
                     **{f"ns_{m}": round(statistics.median(samples[(ratio, m)]), 1) for m in METHODS},
                     "contacts_per_particle": round(report["contact_evaluations"] / (n * report["steps"]), 4),
                     "list_builds": report["list_builds"],
                     **{f"ns_{m}_runs": " ".join(f"{t:.1f}" for t in samples[(ratio, m)]) for m in METHODS}})
    write_results(rows, args, dt, args.out)


if __name__ == "__main__":
    main()
