#!/usr/bin/python3
"""Block steps against velocity Verlet on four workloads (docs/integrators.md, "Cost against
velocity Verlet"): the table of the block-step targets in one command.

  i     bench/hermite-cloud.toml: 3070 grains of 0.5-5 mm fall 0.1 s through water
  ii    the same cloud falls onto the floor and settles (1.5 s; --until cuts it short)
  poly  examples/sedimentation/poly.toml, the representative mixture (S = 0, Sigma = 2, Q_0):
        rain until 0.0678 kg have entered, then until the deposit is at rest
  rain  examples/sedimentation/rain.toml, the main job: rain until 0.2 kg, then at rest

Each workload runs block_hermite (its default step rules, at the largest step dt given
below) and velocity Verlet at the largest step that completes it, side by side: both start at
the same time, one per core, one thread each, so that on an otherwise idle 2-core machine
both see the same machine. --pairs N repeats that N times and reports every pair's ratio,
the median and the spread. Velocity Verlet at twice its step runs after (it fails on i and
ii, which is why its step is what it is), with --check-larger-step.

  /usr/bin/python3 bench/integrators.py [build/tsubu] [--only i,poly,...] [--until T]
      [--pairs N] [--check-larger-step] [--block-set KEY=VALUE ...]

Writes bench/results/integrators[-<only>][-to-<T>s].csv (one row per run) and prints, per
workload, the ratios of evaluations and of wall time, the cost of a block-step particle force
evaluation as a multiple of a velocity Verlet particle-step, and the accuracy measures side
by side (kinetic energy and contacts at the end; for the sedimentation runs the deposit's
porosity, coordination and segregation at rest).
"""
import argparse, csv, json, os, statistics, subprocess, time
from concurrent.futures import ThreadPoolExecutor

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORKLOAD_NAMES = ("i", "ii", "poly", "rain")


def workload_list(text):
    names = text.split(",")
    unknown = [n for n in names if n not in WORKLOAD_NAMES]
    if unknown:
        raise argparse.ArgumentTypeError(f"unknown workload {', '.join(unknown)}; the workloads: {', '.join(WORKLOAD_NAMES)}")
    return names


parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("tsubu", nargs="?", default=os.path.join(root, "build", "tsubu"), help="the executable (build/tsubu)")
parser.add_argument("--only", type=workload_list, help="comma-separated workloads (default: all four)")
parser.add_argument("--until", type=float, help="end every run at this time, s")
parser.add_argument("--pairs", type=int, default=1, help="runs side by side of each workload (default 1)")
parser.add_argument("--check-larger-step", action="store_true", help="velocity Verlet at twice its step after")
parser.add_argument("--block-set", action="append", default=[], metavar="KEY=VALUE",
                    help="a scenario value for the block-step runs only, as tsubu run --set (repeatable), e.g. "
                         "simulation.block_steps.contact_levels='\"own\"'")
arguments = parser.parse_args()
tsubu, only, until, pairs, check_larger = (arguments.tsubu, arguments.only, arguments.until, arguments.pairs,
                                          arguments.check_larger_step)
block_sets = [a for kv in arguments.block_set for a in ("--set", kv)]
out_root = os.path.join(root, "out", "bench-integrators")

CLOUD = os.path.join(root, "bench", "hermite-cloud.toml")
POLY = os.path.join(root, "examples", "sedimentation", "poly.toml")
RAIN = os.path.join(root, "examples", "sedimentation", "rain.toml")
# workload: scenario, duration (None: the scenario's own stop), block-step dt, velocity Verlet dt
WORKLOADS = {"i": (CLOUD, 0.1, 1e-3, 1e-6), "ii": (CLOUD, 1.5, 1e-3, 1e-6),
             "poly": (POLY, None, 1e-3, 5e-7), "rain": (RAIN, None, 1e-3, 2e-6)}
RESULTS = ["porosity", "porosity_standard_error", "coordination", "gamma_upper", "gamma_lower", "deposit_height",
           "deposit_solid_fraction", "deposit_coordination"]


def run(workload, integrator, dt, pair):
    scenario, duration, _, _ = WORKLOADS[workload]
    name = f"{workload}-{integrator}-{dt:g}-{pair}"
    out = os.path.join(out_root, name)
    args = [tsubu, "run", scenario, "--out", out, "--overwrite", "--set", f'simulation.integrator="{integrator}"',
            "--set", f"simulation.dt={dt}"]
    if until or duration:
        args += ["--set", f"simulation.duration={until or duration}"]
    if integrator == "block_hermite":
        args += block_sets
    start = time.monotonic()
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env={**os.environ, "OMP_NUM_THREADS": "1"})
    _, status, usage = os.wait4(proc.pid, 0)
    rc = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - start
    r = json.load(open(os.path.join(out, "run.json")))
    with open(os.path.join(out, "series.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    res = r.get("results", {})
    return {"workload": workload, "pair": pair, "integrator": integrator, "dt": dt, "status": r["status"], "exit": rc,
            "particle_force_evaluations": r["particle_force_evaluations"], "contact_evaluations": r["contact_evaluations"],
            "wall_s": round(wall, 2), "cpu_s": round(usage.ru_utime, 2), "t_end": float(last["time"]),
            "kinetic_end": float(last["kinetic_translational"]), "contacts_end": int(last["contacts"]),
            **{k: res.get(k, "") for k in RESULTS}, "message": r.get("message", "")[:160]}


def summary(workload, runs):
    block = [r for r in runs if r["integrator"] == "block_hermite"]
    verlet = [r for r in runs if r["integrator"] == "velocity_verlet" and r["dt"] == WORKLOADS[workload][3]]
    wall = [v["wall_s"] / b["wall_s"] for b, v in zip(block, verlet)]
    cost = [(b["wall_s"] / b["particle_force_evaluations"]) / (v["wall_s"] / v["particle_force_evaluations"])
            for b, v in zip(block, verlet)]
    b, v = block[0], verlet[0]
    print(f"\n{workload}: evaluations block {b['particle_force_evaluations']:.3e}, velocity Verlet "
          f"{v['particle_force_evaluations']:.3e} ({v['particle_force_evaluations'] / b['particle_force_evaluations']:.1f}x fewer)")
    print(f"{workload}: wall time velocity Verlet / block, pair by pair {[round(x, 3) for x in wall]}, "
          f"median {statistics.median(wall):.3f} (min {min(wall):.3f}, max {max(wall):.3f})")
    print(f"{workload}: a block-step evaluation costs {statistics.median(cost):.1f} velocity Verlet particle-steps "
          f"(pairs {[round(x, 1) for x in cost]})")
    for key in ["status", "t_end", "kinetic_end", "contacts_end"] + RESULTS:
        if b[key] != "" or v[key] != "":
            print(f"{workload}:   {key}: block {b[key]}, velocity Verlet {v[key]}")


rows = []
for w, (_, _, block_dt, verlet_dt) in WORKLOADS.items():
    if only and w not in only:
        continue
    runs = []
    for pair in range(1, pairs + 1):
        with ThreadPoolExecutor(2) as pool:
            both = [("block_hermite", block_dt), ("velocity_verlet", verlet_dt)]
            for row in pool.map(lambda r: run(w, *r, pair), both):
                runs.append({**row, "side_by_side": True})
                print(runs[-1], flush=True)
    if check_larger:
        runs.append(run(w, "velocity_verlet", 2 * verlet_dt, 1))
        print(runs[-1], flush=True)
    summary(w, runs)
    rows += runs
os.makedirs(os.path.join(root, "bench", "results"), exist_ok=True)
suffix = ("-" + "-".join(only) if only else "") + (f"-to-{until:g}s" if until else "") + ("-block-set" if block_sets else "")
path = os.path.join(root, "bench", "results", f"integrators{suffix}.csv")
with open(path, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(dict.fromkeys(k for r in rows for k in r)), restval="")
    w.writeheader()
    w.writerows(rows)
print("wrote", path)
