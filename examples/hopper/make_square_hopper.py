#!/usr/bin/env -S /usr/bin/python3
"""Writes square_hopper.stl (ASCII STL, millimetres): a square bin of 60 mm with a pyramidal
hopper under it, whose faces stand 60 degrees from the horizontal, down to a square outlet of
15 mm (5 bead diameters of 3 mm) at z = 0. Each face is a grid of small triangles, as a CAD
export of a rounded part would be, so that a bead touches several at once.

    /usr/bin/python3 examples/hopper/make_square_hopper.py [--out PATH] [--cells N]
"""
import argparse
import math
import os

OUTLET, BIN, BIN_TOP = 7.5, 30.0, 150.0  # mm: half-widths, and the bin's top
HOPPER_TOP = (BIN - OUTLET) * math.tan(math.radians(60))  # where the hopper meets the bin


def face(point, cells):
    """Triangles of the quadrilateral point(s, t), 0 <= s, t <= 1, as a grid of cells x cells
    quadrilaterals, each cut along alternating diagonals."""
    grid = [[point(i / cells, j / cells) for i in range(cells + 1)] for j in range(cells + 1)]
    tris = []
    for j in range(cells):
        for i in range(cells):
            a, b, c, d = grid[j][i], grid[j][i + 1], grid[j + 1][i + 1], grid[j + 1][i]
            tris += [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
    return tris


def side(k, z0, z1, w0, w1, cells):
    """The k-th side (turned k quarter turns about z) of a frustum from half-width w0 at z0 to
    w1 at z1."""
    def point(s, t):
        w = w0 + (w1 - w0) * t
        x, y = w, -w + 2 * w * s
        c, sn = [(1, 0), (0, 1), (-1, 0), (0, -1)][k]
        return (c * x - sn * y, sn * x + c * y, z0 + (z1 - z0) * t)
    return face(point, cells)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "square_hopper.stl"))
    parser.add_argument("--cells", type=int, default=6)
    args = parser.parse_args()
    tris = []
    for k in range(4):
        tris += side(k, 0.0, HOPPER_TOP, OUTLET, BIN, args.cells)
        tris += side(k, HOPPER_TOP, BIN_TOP, BIN, BIN, args.cells)
    with open(args.out, "w") as f:
        f.write("solid square_hopper\n")
        for t in tris:
            f.write("  facet normal 0 0 0\n    outer loop\n")
            for p in t:
                f.write("      vertex " + " ".join(f"{c:.9g}" for c in p) + "\n")
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid square_hopper\n")
    print(f"{args.out}: {len(tris)} triangles")


if __name__ == "__main__":
    main()
