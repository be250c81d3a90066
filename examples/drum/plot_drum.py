#!/usr/bin/env -S /usr/bin/python3
"""The rotating drum of examples/drum/drum.toml: its bed's dynamic angle of repose over time
and a picture of the last frame.

    PYTHONPATH=build/python python3 examples/drum/plot_drum.py OUT_DIR [--png PATH] [--from T]

The angle of a frame is the inclination of the bed's free surface, measured as the principal
axis of the grains' centres in the plane across the drum (x, z): a bed filling less than half
the drum has the cross-section of a circular segment, whose long axis is its chord, the free
surface. The angle is reported from the frames after --from (default 1 s: the bed lifted
and flowing), with the standard error of the mean over blocks of frames at least 0.25 s long
(successive frames are correlated). Writes OUT_DIR/drum.png (default) and prints the angle.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from tsubu.pictures import draw_grains, save_figure, scenario_walls  # noqa: E402
from tsubu.runs import read_run  # noqa: E402

BLOCK_S = 0.25


def surface_angle(points):
    """Degrees: the inclination of the principal axis of the centres' (x, z), positive when
    the surface rises towards -x, and the centroid."""
    xz = points[:, [0, 2]]
    centre = xz.mean(axis=0)
    values, vectors = np.linalg.eigh(np.cov((xz - centre).T))
    dx, dz = vectors[:, np.argmax(values)]
    if dx < 0:
        dx, dz = -dx, -dz
    return -np.degrees(np.arctan2(dz, dx)), centre


def mean_and_error(times, angles):
    """The mean angle and its standard error over blocks of BLOCK_S seconds."""
    edges = np.arange(times[0], times[-1] + 1e-12, BLOCK_S)
    blocks = [angles[(times >= a) & (times < a + BLOCK_S)].mean() for a in edges if np.any((times >= a) & (times < a + BLOCK_S))]
    if len(blocks) < 2:
        return float(np.mean(angles)), float("nan"), len(blocks)
    return float(np.mean(blocks)), float(np.std(blocks, ddof=1) / np.sqrt(len(blocks))), len(blocks)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--png")
    parser.add_argument("--from", dest="start", type=float, default=1.0)
    args = parser.parse_args()
    run = read_run(args.out_dir)
    if run.frames is None:
        sys.exit(f"{args.out_dir}: no frames (output.vtk_interval)")
    times = np.array(run.frames.times)
    angles = np.array([surface_angle(run.frame(i).points)[0] for i in range(len(times))])
    steady = times >= args.start
    if not np.any(steady):
        sys.exit(f"{args.out_dir}: no frame after {args.start} s")
    mean, error, blocks = mean_and_error(times[steady], angles[steady])
    print(f"dynamic angle of repose {mean:.2f} +- {error:.2f} degrees (standard error over {blocks} blocks of "
          f"{BLOCK_S} s, frames from t = {args.start} s)")

    last = run.frame(-1)
    with open(os.path.join(args.out_dir, "run.json")) as f:
        summary = json.load(f)
    fig, (ax, ax_t) = plt.subplots(1, 2, figsize=(11, 5), gridspec_kw={"width_ratios": [1, 1.3]})
    fig.colorbar(draw_grains(ax, last), ax=ax, label="speed (m/s)", shrink=0.8)
    angle, centre = surface_angle(last.points)
    reach = np.ptp(last.points[:, 0])
    direction = np.array([np.cos(np.radians(angle)), -np.sin(np.radians(angle))])
    line = np.array([centre - 0.6 * reach * direction, centre + 0.6 * reach * direction])
    ax.plot(line[:, 0], line[:, 1], "r-", lw=1.5, label=f"principal axis, {angle:.1f}°")
    for wall in scenario_walls(run):  # the drum
        if wall.get("shape") == "cylinder":
            ax.add_patch(Circle((wall["point"][0], wall["point"][2]), wall["radius"], fill=False, color="0.4"))
    lo, hi = summary["domain"]["lower"], summary["domain"]["upper"]
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[2], hi[2])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.legend(loc="upper right", fontsize="small")
    ax.set_title(f"t = {last.time:.2f} s", fontsize="medium")
    ax_t.plot(times, angles, "k.-", lw=0.8)
    ax_t.axvspan(args.start, times[-1], color="tab:blue", alpha=0.08)
    ax_t.axhline(mean, color="tab:red", lw=1, label=f"{mean:.1f} ± {error:.1f}° (from {args.start} s)")
    ax_t.set_xlabel("t (s)")
    ax_t.set_ylabel("dynamic angle of repose (°)")
    ax_t.legend(fontsize="small")
    ax_t.grid(alpha=0.3)
    save_figure(fig, args.png or os.path.join(args.out_dir, "drum.png"), "Rotating drum (examples/drum/drum.toml)")


if __name__ == "__main__":
    main()
