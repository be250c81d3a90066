"""Drawing helpers for the examples' pictures (matplotlib; the scripts in examples/).

    from tsubu.pictures import draw_grains, save_figure
    collection = draw_grains(ax, run.frame(-1))          # circles in the x-z plane, by speed
    fig.colorbar(collection, ax=ax, label="speed (m/s)")
    save_figure(fig, "out/drum/drum.png")
"""
import numpy as np


def draw_grains(ax, frame, across=(0, 2), values=None, cmap="viridis", select=None):
    """Each grain of `frame` (a Dataset of tsubu.runs) as a circle of its diameter at its
    centre's coordinates `across` (axis indices: (0, 2) is the x-z plane), coloured by
    `values` (default: its speed); only the grains where the boolean array `select` holds,
    when given (a slice). Returns the collection, for a colour bar."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    chosen = np.ones(len(frame["diameter"]), bool) if select is None else np.asarray(select, bool)
    centres = np.asarray(frame.points)[chosen][:, list(across)]
    circles = [Circle(tuple(c), 0.5 * d) for c, d in zip(centres, np.asarray(frame["diameter"])[chosen])]
    collection = PatchCollection(circles, cmap=cmap)
    shade = np.linalg.norm(frame["velocity"], axis=1) if values is None else np.asarray(values)
    collection.set_array(shade[chosen])
    ax.add_collection(collection)
    return collection


def save_figure(fig, png, title=None, dpi=110):
    """The figure laid out (with `title` above it) and written to `png`, which is printed."""
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=dpi)
    print(f"wrote {png}")


def scenario_walls(run):
    """The [[walls]] tables of a run's scenario (read where the run was started from, or from
    its copy beside the checkpoints); [] when neither is there."""
    import os
    import tomllib
    places = [os.path.join(run.path, "checkpoint", "scenario.toml")]
    if run.summary and run.summary.get("scenario"):
        places.insert(0, run.summary["scenario"])
    for scenario in places:
        if os.path.isfile(scenario):
            with open(scenario, "rb") as f:
                return tomllib.load(f).get("walls", [])
    return []


def discharge_run(description):
    """For the scripts that draw a discharge (a chute, a hopper): parses OUT_DIR, --png and
    --frame (default: the middle frame), reads the run, which must have frames and an open
    face, and returns (args, run, frame)."""
    import argparse
    import sys
    from tsubu.runs import read_run
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("out_dir")
    parser.add_argument("--png")
    parser.add_argument("--frame", type=int)
    args = parser.parse_args()
    run = read_run(args.out_dir)
    if run.frames is None or run.outflow is None:
        sys.exit(f"{args.out_dir}: needs frames (output.vtk_interval) and an open face (domain.open)")
    return args, run, run.frame(len(run.frames.times) // 2 if args.frame is None else args.frame)
