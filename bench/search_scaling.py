#!/usr/bin/python3
"""Contact-search cost per particle against the grain-size ratio, CellGrid vs MultiLevelGrid.

Runs tsubu_bench's Search benchmarks (one thread, 5 repetitions, the fastest CPU time of each:
the machine is shared, and the minimum is the least disturbed) and writes
bench/results/search_scaling.{csv,png,md}. Needs Debian's /usr/bin/python3 (numpy, matplotlib).

  /usr/bin/python3 bench/search_scaling.py [path/to/tsubu_bench | saved search_scaling.json]
"""
import csv
import json
import os
import subprocess
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "results")


def run(binary):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    cmd = [binary, "--benchmark_filter=^Search", "--benchmark_format=json", "--benchmark_repetitions=5",
           "--benchmark_min_time=0.3"]
    return json.loads(subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout)


def rows(report):
    fastest = {}
    for b in report["benchmarks"]:
        if b.get("run_type") != "iteration" or b.get("error_occurred"):
            continue
        if b["run_name"] not in fastest or b["cpu_time"] < fastest[b["run_name"]]["cpu_time"]:
            fastest[b["run_name"]] = b
    out = []
    for b in fastest.values():
        kind = b["run_name"].split("/")[0]
        method = {"SearchCell": "cell", "SearchMultiLevel": "multilevel_auto", "SearchLevels": "multilevel_forced"}[kind]
        ms = b["cpu_time"] * {"ms": 1.0, "us": 1e-3, "ns": 1e-6, "s": 1e3}[b["time_unit"]]
        n = b["particles"]
        out.append({"method": method, "ratio": int(b["ratio"]), "levels": int(b["levels"]), "particles": int(n),
                    "pairs": int(b["pairs"]), "ms": ms, "ns_per_particle": ms * 1e6 / n,
                    "estimate": b.get("estimate", ""), "est_cells": b.get("est_cells", ""),
                    "est_candidates": b.get("est_candidates", ""), "est_binning": b.get("est_binning", "")})
    return out


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bench", "tsubu_bench")
    if binary.endswith(".json"):  # re-plot a saved run
        with open(binary) as f:
            report = json.load(f)
    else:
        report = run(binary)
        os.makedirs(OUT, exist_ok=True)
        with open(os.path.join(OUT, "search_scaling.json"), "w") as f:
            json.dump(report, f, indent=1)
    data = rows(report)
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "search_scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(data[0].keys()))
        w.writeheader()
        w.writerows(data)

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for method, style, label in [("cell", "o-", "CellGrid (one level)"), ("multilevel_auto", "s-", "MultiLevelGrid (automatic M_S)")]:
        pts = sorted((r["ratio"], r["ns_per_particle"]) for r in data if r["method"] == method)
        ax1.plot([p[0] for p in pts], [p[1] for p in pts], style, label=label)
    ax1.set_xscale("log")
    ax1.set_xlabel("size ratio d_max / d_min")
    ax1.set_ylabel("find_pairs time per particle (ns)")
    ax1.set_title("~20,000 grains, solid fraction 0.3, n(d) ∝ d^-2")
    ax1.set_ylim(bottom=0)
    ax1.legend()
    ax1.grid(alpha=0.3)

    forced = [r for r in data if r["method"] == "multilevel_forced"]
    # Least squares time = a + b cells + c candidates over every (ratio, M): the cost of a
    # cell visit and of a candidate test, and how far the estimate's terms follow the time.
    cells = np.array([r["est_cells"] for r in forced], float)
    cands = np.array([r["est_candidates"] for r in forced], float)
    ms = np.array([r["ms"] for r in forced], float)
    (a, b, c), *_ = np.linalg.lstsq(np.column_stack([np.ones_like(ms), cells, cands]), ms, rcond=None)
    fitted = {(r["ratio"], r["levels"]): a + b * r["est_cells"] + c * r["est_candidates"] for r in forced}
    ratios = sorted({r["ratio"] for r in forced})
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for color, ratio in zip(colors, ratios):
        pts = sorted((r["levels"], r["ms"]) for r in forced if r["ratio"] == ratio)
        m = [p[0] for p in pts]
        ax2.plot(m, [p[1] for p in pts], "o-", color=color, label=f"ratio {ratio}: measured")
        ax2.plot(m, [fitted[(ratio, k)] for k in m], "x--", color=color, label=f"ratio {ratio}: estimate terms, fitted")
    ax2.set_xlabel("number of levels M_S (forced)")
    ax2.set_ylabel("find_pairs time (ms)")
    ax2.set_title(f"fit: {a:.1f} ms + {b * 1e6:.1f} ns/cell + {c * 1e6:.1f} ns/candidate", fontsize=10)
    ax2.set_ylim(bottom=0)
    ax2.legend(fontsize=7, ncol=2)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "search_scaling.png"), dpi=120)

    ctx = report["context"]
    lines = ["# Contact search: CellGrid vs MultiLevelGrid", "",
             f"{ctx.get('date', '')}, {ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz, "
             "one thread, fastest CPU time of 5 repetitions (bench/search_scaling.py; the machine was shared). Random beds from the engine's "
             "random source: ~20,000 grains, solid fraction 0.3, n(d) ∝ d^-2, periodic in x and y, "
             "margin a tenth of the smallest diameter.", "",
             "| size ratio | particles | pairs | CellGrid ns/particle | MultiLevelGrid ns/particle | auto M_S | best forced M_S (ns/particle) | cell / multilevel |",
             "|---|---|---|---|---|---|---|---|"]
    for ratio in sorted({r["ratio"] for r in data}):
        cell = next(r for r in data if r["method"] == "cell" and r["ratio"] == ratio)
        ml = next(r for r in data if r["method"] == "multilevel_auto" and r["ratio"] == ratio)
        fr = [r for r in forced if r["ratio"] == ratio]
        best = min(fr, key=lambda r: r["ms"]) if fr else None
        best_s = f"{best['levels']} ({best['ns_per_particle']:.0f})" if best else "–"
        lines.append(f"| {ratio} | {cell['particles']} | {cell['pairs']} | {cell['ns_per_particle']:.0f} | "
                     f"{ml['ns_per_particle']:.0f} | {ml['levels']} | {best_s} | {cell['ms'] / ml['ms']:.2f} |")
    lines += ["", "Forced M_S: measured time and the cost estimate (total = 4 cells visited + candidates tested + "
              "cells binned; the terms in 10^6). A least-squares fit over these rows gives "
              f"time = {a:.2f} ms + {b * 1e6:.2f} ns per cell visited + {c * 1e6:.2f} ns per candidate tested.", "",
              "| size ratio | M_S | ms | estimate (10^6) | cells | candidates | binning |", "|---|---|---|---|---|---|---|"]
    for r in sorted(forced, key=lambda r: (r["ratio"], r["levels"])):
        lines.append(f"| {r['ratio']} | {r['levels']} | {r['ms']:.2f} | {r['estimate'] / 1e6:.3f} | "
                     f"{r['est_cells'] / 1e6:.3f} | {r['est_candidates'] / 1e6:.3f} | {r['est_binning'] / 1e6:.3f} |")
    with open(os.path.join(OUT, "search_scaling.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
