#!/usr/bin/python3
"""Plots the piston demonstration (examples/piston-hysteresis.toml) as a stress-strain loop,
next to the single-contact force-overlap curve of the LIGGGHTS reference case driven_reload.

Usage: /usr/bin/python3 validation/hysteresis/plot_piston.py OUT_DIR [PNG]
OUT_DIR is the run's output folder (series.csv); PNG defaults to
docs/validation/hysteresis_piston.png. Needs numpy and matplotlib.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
AREA = 0.012 * 0.012        # m^2, the periodic cross-section of the example
PLATE_START = 0.026         # m, the piston's initial height
LOAD_START = 0.12           # s, end of the sweep: the load cycles begin


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    out_png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "docs", "validation", "hysteresis_piston.png")
    s = np.genfromtxt(os.path.join(sys.argv[1], "series.csv"), delimiter=",", names=True)
    cols = [n for n in s.dtype.names if n.endswith("_displacement")]
    if not cols:
        raise SystemExit("series.csv has no moving wall")
    disp, load = s[cols[0]], s[cols[0].replace("_displacement", "_load")]
    keep = s["time"] >= LOAD_START
    t, disp, load = s["time"][keep], disp[keep], load[keep]
    stress = load / AREA
    # The bed is taken as jammed where the stress first exceeds 5 % of its peak (above the
    # brief load of the sweep); strain counts from there.
    j = np.argmax(stress > 0.05 * stress.max())
    d_j = disp[j]
    strain = (disp - d_j) / (PLATE_START - d_j)

    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    turns = np.r_[0, np.where(np.diff(np.sign(np.diff(disp))) != 0)[0] + 1, len(disp) - 1]
    labels = ["load", "unload", "reload", "unload"]
    for k in range(len(turns) - 1):
        sl = slice(turns[k], turns[k + 1] + 1)
        a.plot(100 * strain[sl], stress[sl] / 1e3, label=labels[k] if k < len(labels) else None)
    a.axhline(0, color="0.6", lw=0.6)
    a.set_xlabel("piston strain (%)")
    a.set_ylabel("piston stress (kPa)")
    a.set_title("256 grains, model HH: piston load cycles")
    a.legend()

    ref = np.genfromtxt(os.path.join(HERE, "reference", "driven_reload.csv"), delimiter=",", names=True,
                        skip_header=1)
    touch = ref["overlap"] > 0
    b.plot(1e6 * ref["overlap"][touch], 1e3 * ref["fn"][touch], ".", ms=2.5, label="LIGGGHTS 3.8 (= tsubu to 1e-14)")
    b.axhline(0, color="0.6", lw=0.6)
    b.set_xlabel("overlap (µm)")
    b.set_ylabel("normal force (mN)")
    b.set_title("one contact, prescribed load-unload-reload (e = 0.7)")
    b.legend()
    fig.tight_layout()
    os.makedirs(os.path.dirname(out_png), exist_ok=True)
    fig.savefig(out_png, dpi=110)
    print("wrote", out_png, "; jammed at piston displacement %.4g m, peak stress %.3g kPa" % (d_j, stress.max() / 1e3))


if __name__ == "__main__":
    main()
