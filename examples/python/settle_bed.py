#!/usr/bin/env -S /usr/bin/python3
"""Settle a small polydisperse bed from Python and draw its solid fraction profile.

    settle_bed.py [--out PATH]      (default: settle_bed.png)

The scenario is examples/settle-poly.toml made smaller with overrides (as the command line's
--set): a 12 x 12 mm box, about 250 grains of 1-3 mm poured from 3 cm. The run is advanced in
pieces; after each the kinetic energy is printed, and at the end the solid fraction of 0.5 mm
slabs is measured on the state in memory (Simulation.analyze) and plotted against height.
Takes about 10 s. Needs `import tsubu` (docs/python.md) and matplotlib.
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tsubu  # noqa: E402

SCENARIO = pathlib.Path(__file__).resolve().parents[1] / "settle-poly.toml"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="settle_bed.png", help="the picture (PNG)")
    args = parser.parse_args()

    sim = tsubu.Simulation(
        SCENARIO,
        overrides={
            "domain.upper": [0.012, 0.012, 0.032],
            "particles.0.upper": [0.012, 0.012, 0.03],
            "simulation.duration": 0.15,
        },
    )
    print(f"{sim.name}: {sim.particle_count} grains, dt = {sim.dt} s")
    for t in np.arange(0.025, sim.duration + 1e-9, 0.025):
        sim.advance_to(t)
        e = sim.energies()
        kinetic = e["kinetic_translational"] + e["kinetic_rotational"]
        print(f"t = {sim.time:.3f} s: kinetic energy {kinetic:.3e} J, {e['contacts']} contacts")

    slab = 0.0005
    top = float(np.max(sim.positions[:, 2] + sim.radii))
    z = np.arange(0.0, top, slab)
    phi = [sim.analyze("solid_fraction", z_range=[a, a + slab])["solid_fraction"] for a in z]
    bulk = sim.analyze("solid_fraction", z_range=[0.002, 0.006])["solid_fraction"]
    print(f"solid fraction of 2 mm < z < 6 mm: {bulk:.3f}")

    fig, ax = plt.subplots(figsize=(4, 5))
    ax.plot(phi, (z + slab / 2) * 1000, drawstyle="steps-mid")
    ax.axvline(bulk, color="grey", linestyle="--", label=f"2-6 mm: {bulk:.3f}")
    ax.set_xlabel("solid fraction")
    ax.set_ylabel("height (mm)")
    ax.set_xlim(0, 0.8)
    ax.set_title(f"{sim.particle_count} grains at t = {sim.time:.2f} s")
    ax.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
