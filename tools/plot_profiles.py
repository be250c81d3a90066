#!/usr/bin/env -S /usr/bin/python3
"""Plots of the profiles a tsubu run wrote with an [[analyses]] entry of type "profiles".

    plot_profiles.py OUT_DIR [--png PATH]      (default PATH: OUT_DIR/profiles/profiles.png)

Reads OUT_DIR/profiles/<quantity>.csv (a row per time, a column per slice centre z; the first
header cell names the quantity and its unit) and draws one panel per quantity against
height: the profile at up to five times spread over the run, the last one in black. The
size panel shows D10, D50 and D90 at the last time; the volume fractions of the size
classes are drawn together at the last time.

Needs Debian's /usr/bin/python3 with python3-numpy and python3-matplotlib.
"""
import argparse
import csv
import glob
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_profile(path):
    """(label, z, times, values[time, slice]) of one profile file; empty cells are NaN."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    label = rows[0][0].split("; ", 1)[1].rsplit(" at slice centre", 1)[0]
    z = np.array([float(c) for c in rows[0][1:]])
    data = np.array([[float(c) if c else np.nan for c in r] for r in rows[1:]]).reshape(-1, len(z) + 1)
    return label, z, data[:, 0], data[:, 1:]


def times_to_show(n):
    """Up to five row indices spread over n rows, the last one included."""
    return sorted(set(np.linspace(0, n - 1, min(n, 5)).round().astype(int)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--png")
    args = parser.parse_args()
    folder = os.path.join(args.out_dir, "profiles")
    png = args.png or os.path.join(folder, "profiles.png")
    panels = ["solid_fraction", "coordination", "velocity_z", "granular_temperature", "velocity_x", "grains"]
    fig, axes = plt.subplots(2, 4, figsize=(16, 8), sharey=True)
    axes = axes.ravel()
    for ax, name in zip(axes, panels):
        label, z, t, v = read_profile(os.path.join(folder, name + ".csv"))
        rows = times_to_show(len(t))
        for n, row in enumerate(rows):
            last = row == rows[-1]
            ax.plot(v[row], z, color="k" if last else plt.cm.viridis(n / max(1, len(rows) - 1)),
                    lw=2 if last else 1, label=f"t = {t[row]:.4g} s")
        ax.set_xlabel(label)
    axes[0].legend(fontsize=7)
    sizes = axes[len(panels)]
    for q, style in (("d10", ":"), ("d50", "-"), ("d90", "--")):
        label, z, t, v = read_profile(os.path.join(folder, q + ".csv"))
        sizes.plot(v[-1], z, "k" + style, label=q.upper())
    sizes.set_xlabel(f"D10, D50, D90 by mass [m] at t = {t[-1]:.4g} s")
    sizes.legend(fontsize=7)
    fractions = axes[len(panels) + 1]
    for path in sorted(glob.glob(os.path.join(folder, "volume_fraction_class*.csv"))):
        label, z, t, v = read_profile(path)
        fractions.plot(v[-1], z, label=label.split(" (", 1)[1].split(")")[0])
    fractions.set_xlabel(f"volume fraction per size class [-] at t = {t[-1]:.4g} s")
    fractions.legend(fontsize=7)
    for ax in axes[::4]:
        ax.set_ylabel("z [m]")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(png)


if __name__ == "__main__":
    main()
