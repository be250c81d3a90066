"""Drawing helpers for the examples' pictures (matplotlib; the scripts in examples/).

    from tsubu.pictures import draw_grains, save_figure
    collection = draw_grains(ax, run.frame(-1))          # circles in the x-z plane, by speed
    fig.colorbar(collection, ax=ax, label="speed (m/s)")
    save_figure(fig, "out/drum/drum.png")
"""
import numpy as np


def draw_grains(ax, frame, across=(0, 2), values=None, cmap="viridis"):
    """Each grain of `frame` (a Dataset of tsubu.runs) as a circle of its diameter at its
    centre's coordinates `across` (axis indices: (0, 2) is the x-z plane), coloured by
    `values` (default: its speed). Returns the collection, for a colour bar."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    centres = np.asarray(frame.points)[:, list(across)]
    circles = [Circle(tuple(c), 0.5 * d) for c, d in zip(centres, frame["diameter"])]
    collection = PatchCollection(circles, cmap=cmap)
    collection.set_array(np.linalg.norm(frame["velocity"], axis=1) if values is None else np.asarray(values))
    ax.add_collection(collection)
    return collection


def save_figure(fig, png, title=None, dpi=110):
    """The figure laid out (with `title` above it) and written to `png`, which is printed."""
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=dpi)
    print(f"wrote {png}")
