#!/usr/bin/env -S /usr/bin/python3
"""Picture of a particle bed from a tsubu run folder.

    render_bed.py OUT_DIR [--png PATH]      (default PATH: OUT_DIR/bed.png)

Reads the last frame listed in OUT_DIR/frames/particles.pvd, OUT_DIR/series.csv and the box from
OUT_DIR/run.json ("domain": {"lower": [..], "upper": [..]}), and draws three panels:
(a) the vertical slice y = y_mid, each sphere cut by it drawn as its circular cross-section and
coloured by diameter; (b) the solid fraction against height, from the exact volume of every
sphere inside each horizontal slab over the full x-y area of the box; (c) the kinetic energy
(translational + rotational) against time.

Needs Debian's /usr/bin/python3 with python3-vtk9, python3-numpy and python3-matplotlib.
"""
import argparse
import csv
import json
import os
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import vtk  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402
from mpl_toolkits.axes_grid1 import make_axes_locatable  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

MM = 1e3


def last_frame(out_dir):
    """(time, centres, diameters) of the last data set listed in frames/particles.pvd."""
    pvd = os.path.join(out_dir, "frames", "particles.pvd")
    frames = ET.parse(pvd).getroot().findall("Collection/DataSet")
    if not frames:
        raise SystemExit(f"{pvd} lists no frames (was the run made with output.vtk_interval = 0?)")
    frame = frames[-1]
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(os.path.dirname(pvd), frame.get("file")))
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfPoints() == 0:
        return float(frame.get("timestep")), np.zeros((0, 3)), np.zeros(0)
    centres = vtk_to_numpy(grid.GetPoints().GetData())
    diameters = vtk_to_numpy(grid.GetPointData().GetArray("diameter"))
    return float(frame.get("timestep")), centres, diameters


def box(out_dir, centres, radii):
    """(lower, upper, note): the domain from run.json, else the extent of the spheres."""
    run_json = os.path.join(out_dir, "run.json")
    if os.path.exists(run_json):
        with open(run_json) as f:
            domain = json.load(f).get("domain")
        if domain:
            return np.array(domain["lower"], float), np.array(domain["upper"], float), ""
    lower = (centres - radii[:, None]).min(axis=0)
    upper = (centres + radii[:, None]).max(axis=0)
    return lower, upper, "\n(no domain in run.json: box = extent of the particles, too small if periodic)"


def slab_volumes(z, r, edges, chunk=4096):
    """Exact volume of the spheres (centres at heights z, radii r) between consecutive edges.

    A sphere's volume below height h is pi (r^2 u - u^3 / 3) + const with u = h - z clipped to
    [-r, r]; summed over the spheres at every edge, its differences are the slab volumes."""
    below = np.zeros(len(edges))
    for s in range(0, len(z), chunk):
        zc, rc = z[s:s + chunk, None], r[s:s + chunk, None]
        u = np.clip(edges[None, :] - zc, -rc, rc)
        below += (np.pi * (rc**2 * u - u**3 / 3)).sum(axis=0)
    return np.diff(below)


def draw_slice(ax, centres, radii, diameters, lower, upper):
    """Cross-sections of the spheres cut by the plane y = y_mid, periodic images across x."""
    y_mid = 0.5 * (lower[1] + upper[1])
    dy = centres[:, 1] - y_mid
    cut = np.abs(dy) < radii
    x, z = centres[cut, 0], centres[cut, 2]
    rho = np.sqrt(radii[cut] ** 2 - dy[cut] ** 2)
    length = upper[0] - lower[0]
    circles, colours = [], []
    for shift in (-length, 0.0, length):  # images show only where a circle crosses a periodic side
        for xi, zi, ri, di in zip(x + shift, z, rho, diameters[cut]):
            if xi + ri > lower[0] and xi - ri < upper[0]:
                circles.append(Circle((xi * MM, zi * MM), ri * MM))
                colours.append(di * MM)
    patches = PatchCollection(circles, cmap="viridis", edgecolor="black", linewidth=0.2)
    patches.set_array(np.array(colours))
    if len(diameters):
        patches.set_clim(diameters.min() * MM, diameters.max() * MM)
    ax.add_collection(patches)
    ax.set_xlim(lower[0] * MM, upper[0] * MM)
    ax.set_ylim(lower[2] * MM, upper[2] * MM)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title(f"(a) slice y = {y_mid * MM:.3g} mm", fontsize="medium")
    return patches


def series_rows(out_dir):
    """The rows of a run's series.csv, as dicts of strings."""
    with open(os.path.join(out_dir, "series.csv")) as f:
        return list(csv.DictReader(f))


def figure_with_slice(figsize, width_ratios, centres, radii, diameters, lower, upper):
    """A figure of two columns: the slice (a) with its colour bar in the first, whose divider
    places profiles beside it, as tall as the slice; returns (fig, grid, ax_slice, divider)."""
    fig = plt.figure(figsize=figsize, layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=width_ratios)
    ax_slice = fig.add_subplot(grid[0])
    divider = make_axes_locatable(ax_slice)
    patches = draw_slice(ax_slice, centres, radii, diameters, lower, upper)
    colour_bar = fig.colorbar(patches, cax=divider.append_axes("right", size=0.15, pad=0.1))
    colour_bar.ax.set_title("diameter\n(mm)", fontsize="small")
    return fig, grid, ax_slice, divider


def render(out_dir, png):
    time, centres, diameters = last_frame(out_dir)
    radii = 0.5 * diameters
    lower, upper, note = box(out_dir, centres, radii)

    fig, grid, ax_slice, divider = figure_with_slice((12, 6), [3, 2], centres, radii, diameters, lower, upper)

    ax_phi = divider.append_axes("right", size=2.2, pad=0.8, sharey=ax_slice)
    width = 0.25 * diameters.min() if len(diameters) else (upper[2] - lower[2]) / 100
    edges = np.linspace(lower[2], upper[2], max(1, round((upper[2] - lower[2]) / width)) + 1)
    area = (upper[0] - lower[0]) * (upper[1] - lower[1])
    phi = slab_volumes(centres[:, 2], radii, edges) / (area * np.diff(edges))
    ax_phi.stairs(phi, edges * MM, orientation="horizontal", baseline=None)
    ax_phi.set_xlim(0, 1)
    ax_phi.set_xlabel("solid fraction")
    ax_phi.set_title("(b) profile", fontsize="medium")
    ax_phi.tick_params(labelleft=False)
    ax_phi.grid(alpha=0.3)

    ax_ke = fig.add_subplot(grid[1])
    rows = series_rows(out_dir)
    t = np.array([float(r["time"]) for r in rows])
    ke = np.array([float(r["kinetic_translational"]) + float(r["kinetic_rotational"]) for r in rows])
    ax_ke.semilogy(t[ke > 0], ke[ke > 0])  # log axis: the state at rest (0 J) is left out
    ax_ke.set_xlabel("time (s)")
    ax_ke.set_ylabel("kinetic energy (J)")
    ax_ke.set_title("(c) kinetic energy, translational + rotational", fontsize="medium")
    ax_ke.grid(alpha=0.3)

    fig.suptitle(f"{len(diameters)} particles at t = {time:.4g} s{note}")
    fig.savefig(png, dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir", help="folder written by `tsubu run --out`")
    parser.add_argument("--png", help="output picture (default: OUT_DIR/bed.png)")
    args = parser.parse_args()
    png = args.png or os.path.join(args.out_dir, "bed.png")
    render(args.out_dir, png)
    print(png)


if __name__ == "__main__":
    main()
