#!/usr/bin/env python3
"""Fixed-step speed of two tsubu executables on the shared benchmark beds, alternated.

A change of the engine must not cost speed. This runs OLD and NEW in turn (OLD NEW OLD
NEW ...) on the same bed, one thread each, after one warm-up run of each, and reads each
run's particle-steps per second of its time loop (run.json, particle_steps_per_second:
the loop alone, without reading the bed). It prints every pair's ratio NEW/OLD, their
median and their spread (min, max): alternation makes the ratio robust to the machine's
drift; the spread says how far to trust it. Run it on an idle machine.

    python3 bench/compare_binaries.py OLD_TSUBU NEW_TSUBU [--beds mono-settled poly10-settled]
        [--pairs 5] [--threads 1] [--set KEY=VALUE ...] [--markdown]

A bed is bench/<bed>.toml (their particles come from ../shared/bench/, see
bench/compare_peers.sh) or the path of any scenario file, with --set overrides given to both
binaries alike. A sedimentation run (model H, the still fluid, the inflow), for example:

    python3 bench/compare_binaries.py OLD_TSUBU NEW_TSUBU --pairs 3 \
        --beds examples/sedimentation/poly.toml \
        --set particles.0.distribution.spread=1.3863 --set simulation.duration=0.9

OLD_TSUBU is, for example, a build of the commit before the change (see
tools/compare_runs.py for how to build one beside the checkout).
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent


def scenario_of(bed):
    """A bench bed by name (bench/<bed>.toml) or a scenario file by its path."""
    return bed if bed.endswith(".toml") else str(HERE / f"{bed}.toml")


def rate(tsubu, bed, threads, out, sets):
    cmd = [tsubu, "run", scenario_of(bed), "--out", str(out), "--overwrite", "--threads", str(threads),
           "--set", "output.vtk_interval=0", "--set", "output.checkpoint_every_steps=0",
           "--set", "output.checkpoint_every_seconds=0"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    return json.loads((out / "run.json").read_text())["particle_steps_per_second"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--beds", nargs="+", default=["mono-settled", "poly10-settled"])
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="an override for both binaries")
    ap.add_argument("--markdown", action="store_true", help="print the summary as a Markdown table")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        for bed in args.beds:
            rate(args.old, bed, args.threads, work / "old", args.set)  # warm-up: the bed file in the page cache
            rate(args.new, bed, args.threads, work / "new", args.set)
            ratios, olds, news = [], [], []
            for k in range(args.pairs):
                old = rate(args.old, bed, args.threads, work / "old", args.set)
                new = rate(args.new, bed, args.threads, work / "new", args.set)
                olds.append(old), news.append(new), ratios.append(new / old)
                print(f"{bed} pair {k + 1}: old {old:.4g}, new {new:.4g} particle-steps/s, new/old {new / old:.3f}",
                      flush=True)
            rows.append((bed, statistics.median(olds), statistics.median(news), statistics.median(ratios),
                         min(ratios), max(ratios)))
    if args.markdown:
        print(f"\n| bed | old, particle-steps/s | new | new/old, median of {args.pairs} pairs | min | max |")
        print("|---|---|---|---|---|---|")
        for bed, old, new, med, lo, hi in rows:
            print(f"| {bed} | {old:.3g} | {new:.3g} | {med:.3f} | {lo:.3f} | {hi:.3f} |")
    else:
        for bed, old, new, med, lo, hi in rows:
            print(f"{bed}: new/old {med:.3f} (median of {args.pairs} pairs; min {lo:.3f}, max {hi:.3f});"
                  f" old {old:.4g}, new {new:.4g} particle-steps/s")


if __name__ == "__main__":
    main()
