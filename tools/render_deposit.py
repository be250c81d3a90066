#!/usr/bin/env -S /usr/bin/python3
"""Picture of a deposit from a tsubu sedimentation run (the main job, tools/demo.sh).

    render_deposit.py OUT_DIR [--png PATH]      (default PATH: OUT_DIR/deposit.png)

Needs a run with frames (output.vtk_interval > 0) and an [[analyses]] entry of type
"profiles". Draws four panels: (a) the vertical slice y = y_mid of the last frame, the
spheres cut by it coloured by diameter (as tools/render_bed.py); (b) the porosity 1 - phi
against height at the last profile row, with the run's mean porosity on its measuring band
when the run reports one; (c) the grading against height, D10, D50 and D90 by mass of the
grains in each slice; (d) the deposit height and the grains in the box against time.

Needs Debian's /usr/bin/python3 with python3-vtk9, python3-numpy and python3-matplotlib.
"""
import argparse
import csv
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from plot_profiles import read_profile  # noqa: E402
from render_bed import MM, box, figure_with_slice, last_frame, series_rows  # noqa: E402


def profile_at_end(out_dir, name):
    """(label, z, values at the last row) of profiles/<name>.csv."""
    label, z, times, values = read_profile(os.path.join(out_dir, "profiles", name + ".csv"))
    return label, z, times[-1], values[-1]


def render(out_dir, png):
    time, centres, diameters = last_frame(out_dir)
    radii = 0.5 * diameters
    lower, upper, _ = box(out_dir, centres, radii)
    with open(os.path.join(out_dir, "run.json")) as f:
        summary = json.load(f)
    results = summary.get("results", {})

    fig, grid, ax_slice, divider = figure_with_slice((15, 6), [3, 1.4], centres, radii, diameters, lower, upper)

    ax_por = divider.append_axes("right", size=2.0, pad=0.8, sharey=ax_slice)
    _, z, t_end, phi = profile_at_end(out_dir, "solid_fraction")
    filled = phi > 0
    ax_por.plot(1 - phi[filled], z[filled] * MM, "k.-")
    if "porosity" in results:
        ax_por.axvline(results["porosity"], color="tab:red", lw=1, label=f"porosity {results['porosity']:.3f}")
        ax_por.legend(fontsize="small", loc="upper left")
    ax_por.set_xlim(0.2, 1)
    ax_por.set_xlabel("porosity 1 - φ")
    ax_por.set_title(f"(b) porosity, t = {t_end:.3g} s", fontsize="medium")
    ax_por.tick_params(labelleft=False)
    ax_por.grid(alpha=0.3)

    ax_grade = divider.append_axes("right", size=2.0, pad=0.3, sharey=ax_slice)
    for quantity, style in (("d10", ":"), ("d50", "-"), ("d90", "--")):
        _, z, _, d = profile_at_end(out_dir, quantity)
        ax_grade.plot(d * MM, z * MM, "k" + style, label=quantity.upper())
    ax_grade.set_xlabel("diameter by mass (mm)")
    ax_grade.set_title("(c) grading", fontsize="medium")
    ax_grade.legend(fontsize="small", loc="upper right")
    ax_grade.tick_params(labelleft=False)
    ax_grade.grid(alpha=0.3)

    ax_time = fig.add_subplot(grid[1])
    rows = series_rows(out_dir)
    t = np.array([float(r["time"]) for r in rows])
    if rows and "deposit_height" in rows[0]:
        ax_time.plot(t, [float(r["deposit_height"]) * MM for r in rows], "k", label="deposit height (mm)")
    if rows and "particles" in rows[0]:
        ax_grains = ax_time.twinx()
        ax_grains.plot(t, [float(r["particles"]) for r in rows], "tab:blue", lw=1)
        ax_grains.set_ylabel("grains in the box", color="tab:blue")
    ax_time.set_xlabel("time (s)")
    ax_time.set_ylabel("deposit height (mm)")
    ax_time.set_title("(d) deposit height and grains", fontsize="medium")
    ax_time.grid(alpha=0.3)

    stats = ", ".join(f"{k} = {results[k]:.3g}" for k in ("porosity", "coordination") if k in results)
    fig.suptitle(f"{summary.get('name', '')}: {len(diameters)} grains at t = {time:.3g} s "
                 f"({summary.get('integrator', '')}){'; ' + stats if stats else ''}")
    fig.savefig(png, dpi=110)
    print(png)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--png")
    args = parser.parse_args()
    render(args.out_dir, args.png or os.path.join(args.out_dir, "deposit.png"))


if __name__ == "__main__":
    main()
