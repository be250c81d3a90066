#!/usr/bin/env -S /usr/bin/python3
"""A hopper of examples/hopper/ discharging (hopper.toml, conical; square_hopper.toml, a triangle
mesh): a cut through its axis (the beads within one bead diameter of the plane y = 0, coloured
by their speed, and the walls' trace in that plane) and the mass discharged over time with its
steady rate.

    PYTHONPATH=build/python python3 examples/hopper/plot_hopper.py OUT_DIR [--png PATH] [--frame I]

--frame picks the frame drawn (default: the middle one). The steady rate is the slope of a
straight line through the discharged mass between 20 % and 80 % of the mass that left (the
start and the end of a discharge are not steady). Writes OUT_DIR/hopper.png (default) and
prints the mass discharged and the rate.
"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from tsubu.pictures import discharge_run, draw_grains, save_figure, scenario_walls  # noqa: E402


def steady_rate(times, masses):
    """kg/s: the slope of the cumulative discharged mass between 20 % and 80 % of its total;
    NaN when fewer than ten beads are in that stretch."""
    total = np.cumsum(masses)
    if len(total) == 0:
        return float("nan")
    inside = (total >= 0.2 * total[-1]) & (total <= 0.8 * total[-1])
    if inside.sum() < 10:
        return float("nan")
    return float(np.polyfit(times[inside], total[inside], 1)[0])


def mesh_cut(path, factor):
    """The segments where the triangles of an ASCII STL file (coordinates times `factor`, in
    m) cross the plane y = 0, as [((x0, z0), (x1, z1)), ...]."""
    with open(path) as f:
        corners = [[float(c) * factor for c in line.split()[1:4]] for line in f if line.split()[:1] == ["vertex"]]
    segments = []
    for k in range(0, len(corners) - 2, 3):
        triangle = corners[k:k + 3]
        crossings = []
        for a, b in ((0, 1), (1, 2), (2, 0)):
            p, q = triangle[a], triangle[b]
            if (p[1] < 0) != (q[1] < 0):
                s = p[1] / (p[1] - q[1])
                crossings.append((p[0] + s * (q[0] - p[0]), p[2] + s * (q[2] - p[2])))
        if len(crossings) == 2:
            segments.append(tuple(crossings))
    return segments


def outline(ax, walls, folder):
    """The cone, cylinder and mesh walls' traces in the plane y = 0 (a mesh's file is read
    from the scenario's folder)."""
    units = {"m": 1.0, "cm": 0.01, "mm": 0.001, "um": 1e-6, "in": 0.0254}
    for wall in walls:
        shape = wall.get("shape", "plane")
        if shape == "mesh" and wall["file"].lower().endswith(".stl") and "rotation_axis" not in wall:
            factor = units[wall["units"]] * wall.get("scale", 1.0)
            shift = wall.get("translate", [0, 0, 0])
            for (x0, z0), (x1, z1) in mesh_cut(os.path.join(folder, wall["file"]), factor):
                ax.plot([x0 + shift[0], x1 + shift[0]], [z0 + shift[2], z1 + shift[2]], "k", lw=1.5)
        if shape == "cone":
            z0, z1 = wall["point"][2], wall["point"][2] + wall["length"]
            for side in (-1, 1):
                ax.plot([side * wall["radius"], side * wall["end_radius"]], [z0, z1], "k", lw=1.5)
        elif shape == "cylinder":
            for side in (-1, 1):
                ax.axvline(side * wall["radius"], color="k", lw=1.5)


def main():
    args, run, frame = discharge_run(__doc__.splitlines()[0])
    times, masses = np.asarray(run.outflow["time"], float), np.asarray(run.outflow["mass"], float)
    rate = steady_rate(times, masses)
    print(f"{len(times)} beads left by t = {run.series['time'][-1]:.2f} s ({masses.sum() * 1e3:.2f} g); "
          f"steady discharge rate {rate * 1e3:.2f} g/s")

    fig, (ax, ax_out) = plt.subplots(1, 2, figsize=(10, 5.5), gridspec_kw={"width_ratios": [1, 1.3]})
    cut = np.abs(np.asarray(frame.points)[:, 1]) < np.asarray(frame["diameter"])  # a slice through the axis
    fig.colorbar(draw_grains(ax, frame, select=cut), ax=ax, label="speed (m/s)", shrink=0.8)
    scenario = run.summary.get("scenario", "")
    outline(ax, scenario_walls(run), os.path.dirname(scenario))
    lo, hi = run.summary["domain"]["lower"], run.summary["domain"]["upper"]
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[2], hi[2])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.set_title(f"cut through the axis, t = {frame.time:.2f} s", fontsize="medium")
    ax_out.plot(times, np.cumsum(masses) * 1e3, "k", label="discharged mass")
    if np.isfinite(rate):
        ax_out.set_title(f"steady rate {rate * 1e3:.1f} g/s (20-80 % of the mass)", fontsize="medium")
    ax_out.set_xlabel("t (s)")
    ax_out.set_ylabel("mass discharged (g)")
    ax_out.grid(alpha=0.3)
    save_figure(fig, args.png or os.path.join(args.out_dir, "hopper.png"),
                f"Hopper discharging ({os.path.relpath(scenario) if scenario else 'examples/hopper'})")


if __name__ == "__main__":
    main()
