#!/usr/bin/env python3
"""Strong scaling of a run split among processes (docs/parallel.md), against LAMMPS.

On each bed it runs, in turn and repeatedly (alternated, so that the machine's drift falls
on every configuration alike): tsubu on one process of one thread, on two processes of one
thread (mpirun -np 2), on one process of two threads, and, when installed, LAMMPS (`lmp`,
the shared benchmark's input) on one and on two processes. A rate is particle-steps per
second of the time loop (tsubu's run.json, LAMMPS's "Loop time"); a speed-up is the ratio of
two rates of the same round. It prints each round and a table: the median speed-up over
the rounds with its spread (min, max), the parallel efficiency (speed-up / processes) and
the peak resident set of the largest process.

    python3 bench/scaling.py [--beds mono-settled-large sedimentation] [--rounds 3]
        [--tsubu build/tsubu] [--markdown] [--csv FILE]
    python3 bench/scaling.py --memory 1000000     # bytes per grain on 1 and 2 processes

Beds: a shared benchmark bed by name (bench/<bed>.toml, for example `mono-settled-large`, the
100,000-grain settled bed, 1000 steps; LAMMPS runs it too, as many steps), `sedimentation` (examples/sedimentation/poly.toml to
t = 0.35 s: the inflow raining onto a growing deposit, about 1300 grains at the end), or
the path of any scenario file. `--set KEY=VALUE` is given to every tsubu run (for example
`--set parallel.counts=[2,1,1]`). Run it on an idle machine with at least two cores.

`--memory N` runs N grains (a simple cubic lattice at rest on a floor, 20 steps) on one and
on two processes and prints each process's peak resident set per grain of the whole run.
"""
import argparse
import json
import os
import pathlib
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import tomllib

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
SHARED = ROOT.parent / "shared" / "bench"
SEDIMENTATION = (ROOT / "examples" / "sedimentation" / "poly.toml", ["simulation.duration=0.35"])
QUIET = ["output.vtk_interval=0", "output.checkpoint_every_steps=0", "output.checkpoint_every_seconds=0"]


def mpirun(processes):
    return [shutil.which("mpirun") or "mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(processes)]


def peak_rss(folder, processes, command):
    """Runs command under GNU time in each process; the largest peak resident set in bytes."""
    files = [folder / f"rss.{r}" for r in range(processes)]
    timed = ["/usr/bin/time", "-f", "%M", "-o"]
    if processes == 1:
        full = timed + [str(files[0])] + command
    else:  # each process writes its own peak (Open MPI names the rank in the environment)
        script = 'exec /usr/bin/time -f %M -o "$0.$OMPI_COMM_WORLD_RANK" "$@"'
        full = mpirun(processes) + ["sh", "-c", script, str(folder / "rss")] + command
    r = subprocess.run(full, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    if r.returncode != 0:
        sys.exit(f"{' '.join(full)} failed ({r.returncode}):\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    return max(int(f.read_text().split()[-1]) for f in files) * 1024, r.stdout


def tsubu_rate(tsubu, scenario, sets, processes, threads, work):
    out = work / f"tsubu-{processes}x{threads}"
    command = [tsubu, "run", str(scenario), "--out", str(out), "--overwrite", "--threads", str(threads)]
    for s in QUIET + sets:
        command += ["--set", s]
    rss, _ = peak_rss(work, processes, command)
    run = json.loads((out / "run.json").read_text())
    return run["particle_steps_per_second"], rss


def lammps_rate(data, case, processes, work):
    meta = json.loads((SHARED / f"{case}.json").read_text())
    skin = "0.4e-3" if case.startswith("mono") else "0.1e-3"  # the peers' skins (shared README)
    simulation = tomllib.loads((HERE / f"{case}.toml").read_text())["simulation"]
    steps = round(simulation["duration"] / simulation["dt"])  # as many as tsubu's bed file
    command = ["lmp", "-in", str(SHARED / "lammps" / "bench_lmp.in"), "-log", "none", "-var", "data", str(data),
               "-var", "dt", str(meta["dt"]), "-var", "nsteps", str(steps), "-var", "skin", skin, "-var", "nmul", "0"]
    rss, stdout = peak_rss(work, processes, command)
    loop = re.search(r"^Loop time of (\S+) on \d+ procs for (\d+) steps with (\d+) atoms", stdout, re.M)
    return int(loop[3]) * int(loop[2]) / float(loop[1]), rss


def configurations(bed, args, work):
    """(name, processes, run()) of a bed; run() gives (rate, peak rss)."""
    shared = (HERE / f"{bed}.toml").exists()  # a shared benchmark bed, which LAMMPS runs too
    scenario, sets = SEDIMENTATION if bed == "sedimentation" else (HERE / f"{bed}.toml" if shared else bed, [])
    sets = sets + args.set
    confs = [(f"tsubu {p} process{'es' if p > 1 else ''} x {t} thread{'s' if t > 1 else ''}", p * t,
              lambda p=p, t=t: tsubu_rate(args.tsubu, scenario, sets, p, t, work))
             for p, t in ((1, 1), (2, 1), (1, 2))]
    if shared and shutil.which("lmp") and (SHARED / f"{bed}.csv").exists():
        data = work / f"{bed}.data"
        if not data.exists():
            subprocess.run([sys.executable, str(SHARED / "tools" / "csv2lammps.py"), str(SHARED / f"{bed}.csv"),
                            str(data)], check=True, capture_output=True)
        confs += [(f"LAMMPS {p} process{'es' if p > 1 else ''}", p, lambda p=p: lammps_rate(data, bed, p, work))
                  for p in (1, 2)]
    return confs


def scale(args):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        for bed in args.beds:
            confs = configurations(bed, args, work)
            for _, _, run in confs:
                run()  # warm-up: the bed in the page cache
            rates = {name: [] for name, _, _ in confs}
            rss = {name: 0 for name, _, _ in confs}
            for k in range(args.rounds):
                order = confs[k % len(confs):] + confs[:k % len(confs)]  # each configuration leads in turn
                for name, _, run in order:
                    rate, peak = run()
                    rates[name].append(rate)
                    rss[name] = max(rss[name], peak)
                print(f"{bed} round {k + 1}: " + ", ".join(f"{n} {rates[n][-1]:.3g}" for n, _, _ in confs), flush=True)
            base = {"tsubu": confs[0][0], "LAMMPS": next((n for n, _, _ in confs if n.startswith("LAMMPS")), None)}
            for name, cores, _ in confs:
                one = rates[base[name.split()[0]]]
                speedups = [r / o for r, o in zip(rates[name], one)]
                rows.append(dict(bed=bed, configuration=name, cores=cores, rate=statistics.median(rates[name]),
                                 speedup=statistics.median(speedups), low=min(speedups), high=max(speedups),
                                 efficiency=statistics.median(speedups) / cores, peak_rss=rss[name]))
    return rows


def lattice_overrides(grains):
    """The 100k bed's physics (bench/mono-settled-large.toml) with `grains` 2 mm spheres on a
    simple cubic lattice (n x n x layers) just above its floor instead of its bed, 20 steps."""
    d, n = 0.002, max(1, round((grains / 10) ** 0.5))
    layers = -(-grains // (n * n))
    side, height = n * 1.01 * d, (layers + 2) * 1.01 * d
    lattice = (f'{{source = "lattice", material = "grain", lower = [0, 0, 0], upper = [{side!r}, {side!r}, '
               f'{layers * 1.01 * d!r}], diameter = {d!r}, spacing = {1.01 * d!r}}}')
    return [f"simulation.duration={20 * 5e-6!r}", f"domain.upper=[{side!r}, {side!r}, {height!r}]",
            f"particles=[{lattice}]"], n * n * layers


def memory(args):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        sets, grains = lattice_overrides(args.memory)
        for processes in (1, 2):
            _, rss = tsubu_rate(args.tsubu, HERE / "mono-settled-large.toml", sets, processes, 1, work)
            rows.append((processes, grains, rss))
            print(f"{grains} grains on {processes} process{'es' if processes > 1 else ''}: peak resident set of the "
                  f"largest process {rss / 2**20:.0f} MiB, {rss / grains:.0f} bytes per grain of the run", flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--beds", nargs="+", default=["mono-settled-large", "sedimentation"])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--tsubu", default=str(ROOT / "build" / "tsubu"))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="an override for every tsubu run")
    ap.add_argument("--memory", type=int, metavar="N", help="peak memory of N grains on 1 and 2 processes instead")
    ap.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    ap.add_argument("--csv", type=pathlib.Path, help="write the table to this CSV file")
    args = ap.parse_args()
    if args.memory:
        memory(args)
        return
    rows = scale(args)
    if args.csv:
        keys = list(rows[0])
        args.csv.write_text(",".join(keys) + "\n" + "".join(",".join(str(r[k]) for k in keys) + "\n" for r in rows))
    if args.markdown:
        print(f"\n| bed | configuration | particle-steps/s | speed-up, median of {args.rounds} | min | max |"
              " efficiency | peak RSS, largest process |")
        print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        if args.markdown:
            print(f"| {r['bed']} | {r['configuration']} | {r['rate']:.3g} | {r['speedup']:.2f} | {r['low']:.2f} | "
                  f"{r['high']:.2f} | {r['efficiency']:.2f} | {r['peak_rss'] / 2**20:.0f} MiB |")
        else:
            print(f"{r['bed']}: {r['configuration']}: {r['rate']:.3g} particle-steps/s, speed-up {r['speedup']:.2f} "
                  f"({r['low']:.2f}-{r['high']:.2f}), efficiency {r['efficiency']:.2f}, "
                  f"peak {r['peak_rss'] / 2**20:.0f} MiB")


if __name__ == "__main__":
    main()
