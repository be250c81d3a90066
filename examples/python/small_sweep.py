#!/usr/bin/env -S /usr/bin/python3
"""A small sweep and its plot: the monodisperse sedimentation example at two fluxes and two
seeds (examples/sedimentation/sweeps/ci.toml, 4 runs of a few seconds), then the porosity and
coordination number of each deposit against the flux, and the grains in the box over time.

    /usr/bin/python3 examples/python/small_sweep.py [--png PATH]

Run from the repository's root (the sweep writes out/sweeps/ci/; re-running reuses the
finished runs). Needs numpy and matplotlib; the tsubu executable is found as the sweep finds
it ($TSUBU_BINARY, tsubu on the PATH, build/tsubu). docs/sweeps.md describes both modules.
"""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from tsubu.runs import read_run
from tsubu.sweep import run_sweep

PHI_0 = 0.1  # the paper's highest flux Q_0 (docs/sedimentation.md)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--png", default="out/sweeps/ci/small_sweep.png", help="the picture to write")
    args = parser.parse_args()
    cases = run_sweep(ROOT / "examples" / "sedimentation" / "sweeps" / "ci.toml")
    failed = [c.name for c in cases if c.status != "ok"]
    if failed:
        sys.exit(f"not finished: {', '.join(failed)} (see out/sweeps/ci/logs/)")

    fig, (ax_por, ax_z, ax_h) = plt.subplots(1, 3, figsize=(13, 4), layout="constrained")
    for case in cases:
        run = read_run(case.folder)
        q = case.params["particles.0.solid_fraction"] / PHI_0
        seed = case.params["simulation.seed"]
        marker = "o" if seed == 1 else "s"
        ax_por.plot(q, run.results["porosity"], marker, color="C0")
        ax_por.plot(q, run.results["porosity_exact"], marker, color="C1", mfc="none")
        ax_z.plot(q, run.results["coordination"], marker, color="C0")
        ax_z.plot(q, run.results["coordination_no_rattlers_4"], marker, color="C1", mfc="none")
        ax_h.plot(run.series["time"], run.series["particles"], label=f"Q/Q0 = {q:g}, seed {seed}")
    for ax in (ax_por, ax_z):
        ax.set_xlim(0, 1.1)
        ax.set_xlabel("Q / Q0")
        ax.grid(alpha=0.3)
    ax_por.set_ylabel("porosity of 0.15 L < z < 0.35 L")
    ax_por.legend(["Monte Carlo", "exact"], fontsize="small")
    ax_z.set_ylabel("coordination number Z")
    ax_z.legend(["all grains", "fewer than 4 contacts left out"], fontsize="small")
    ax_h.set_xlabel("time (s)")
    ax_h.set_ylabel("grains in the box (to rest)")
    ax_h.legend(fontsize="small")
    ax_h.grid(alpha=0.3)
    fig.suptitle("One size, d = 1 cm, L = 4 d, deposits at rest: circles seed 1, squares seed 2")
    Path(args.png).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.png, dpi=110)
    print(args.png)


if __name__ == "__main__":
    main()
