#!/usr/bin/python3
"""Block steps against velocity Verlet on bench/hermite-cloud.toml (docs/integrators.md).

Workload (i): the cloud falls 0.1 s through water, before any grain reaches the floor.
Workload (ii): the same cloud falls onto the floor and settles (1.5 s).
Each workload runs block_hermite with its default rules and velocity Verlet at the largest
step that completes it (smaller steps are listed too: a step that fails is reported as such),
and writes bench/results/integrators.{csv,md}: particle force evaluations, wall and CPU time,
and the accuracy measures (kinetic energy at the end, tracked grains, the deposit's solid
fraction and coordination).

  /usr/bin/python3 bench/integrators.py [build/tsubu] [--only i|ii] [--until T] [--side-by-side]

--until T ends each run of the workload at T seconds of simulated time instead (the full
settling of (ii) takes block steps about an hour). --side-by-side runs block steps and
velocity Verlet at 1 us at the same time, one per core, and the other runs after: the two
then share the machine's state, and the ratio of their times is fair on a 2-core machine
that is otherwise idle (each still runs on one thread).
"""
import csv, json, os, subprocess, sys, time
from concurrent.futures import ThreadPoolExecutor

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
def option(name):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else None


values = {option("--only"), option("--until")}
tsubu = next((a for a in sys.argv[1:] if not a.startswith("--") and a not in values), os.path.join(root, "build", "tsubu"))
only = option("--only")
until = float(option("--until")) if option("--until") else None
side_by_side = "--side-by-side" in sys.argv
scenario = os.path.join(root, "bench", "hermite-cloud.toml")
out_root = os.path.join(root, "out", "bench-integrators")

WORKLOADS = {"i": 0.1, "ii": 1.5}
RUNS = [("block_hermite", None), ("velocity_verlet", 1e-6), ("velocity_verlet", 2e-6)]


def run(workload, integrator, dt):
    name = f"{workload}-{integrator}" + (f"-{dt:g}" if dt else "")
    out = os.path.join(out_root, name)
    args = [tsubu, "run", scenario, "--out", out, "--overwrite", "--set", f"simulation.duration={until or WORKLOADS[workload]}",
            "--set", f'simulation.integrator="{integrator}"']
    if dt:
        args += ["--set", f"simulation.dt={dt}"]
    start = time.monotonic()
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env={**os.environ, "OMP_NUM_THREADS": "1"})
    _, status, usage = os.wait4(proc.pid, 0)
    rc = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - start
    cpu = usage.ru_utime
    r = json.load(open(os.path.join(out, "run.json")))
    with open(os.path.join(out, "series.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    res = r.get("results", {})
    return {"workload": workload, "integrator": integrator, "dt": dt or r["dt"], "status": r["status"], "exit": rc,
            "particle_force_evaluations": r["particle_force_evaluations"], "contact_evaluations": r["contact_evaluations"],
            "wall_s": round(wall, 2), "cpu_s": round(cpu, 2), "t_end": float(last["time"]),
            "kinetic_end": float(last["kinetic_translational"]), "contacts_end": int(last["contacts"]),
            "solid_fraction": res.get("deposit_solid_fraction", ""), "coordination": res.get("deposit_coordination", ""),
            "message": r.get("message", "")[:160]}


rows = []
for w in WORKLOADS:
    if only and w != only:
        continue
    runs = RUNS
    if side_by_side:
        with ThreadPoolExecutor(2) as pool:
            for row in pool.map(lambda r: run(w, *r), RUNS[:2]):
                rows.append({**row, "side_by_side": True})
                print(rows[-1], flush=True)
        runs = RUNS[2:]
    for integrator, dt in runs:
        rows.append(run(w, integrator, dt))
        print(rows[-1], flush=True)
os.makedirs(os.path.join(root, "bench", "results"), exist_ok=True)
path = os.path.join(root, "bench", "results",
                    "integrators" + (f"-{only}" if only else "") + (f"-to-{until:g}s" if until else "") + ".csv")
with open(path, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(dict.fromkeys(k for r in rows for k in r)), restval="")
    w.writeheader()
    w.writerows(rows)
print("wrote", path)
