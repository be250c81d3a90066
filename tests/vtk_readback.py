#!/usr/bin/env -S /usr/bin/python3
"""Reads tsubu's VTK output back with the real VTK readers and compares it with a reference.

    vtk_readback.py FRAME.vtu REF      every point-data array and the points, bit for bit
    vtk_readback.py --pvd INDEX.pvd REF   the collection's time steps and file names, exactly

Driven by tests/unit/test_vtk_readback.cpp, which writes REF. Exit codes: 0 match, 1 mismatch
(the first one is printed), 77 when this Python has no vtk or numpy (the caller skips).

REF for a .vtu: blocks of "NAME TYPE COMPONENTS TUPLES" followed by TUPLES lines of values
(%.17g, so parsing them gives the exact doubles); the block named "Points" holds the points,
every other block is a point-data array, and the file must hold exactly those arrays.
REF for a .pvd: one "TIME FILE POINTS" line per data set, in order.
"""
import os
import sys
import xml.etree.ElementTree as ET

try:
    import numpy as np
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError as e:
    print(f"skip: /usr/bin/python3 cannot import vtk/numpy ({e})")
    sys.exit(77)

DTYPES = {"Int32": np.int32, "Int64": np.int64, "UInt8": np.uint8, "Float64": np.float64}


class Mismatch(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Mismatch(message)


def read_reference(path):
    with open(path) as f:
        lines = [line.split() for line in f if line.strip() and not line.startswith("#")]
    blocks, i = {}, 0
    while i < len(lines):
        name, vtype, ncomp, ntup = lines[i]
        ncomp, ntup = int(ncomp), int(ntup)
        parse = float if vtype.startswith("Float") else int
        rows = [[parse(v) for v in row] for row in lines[i + 1:i + 1 + ntup]]
        blocks[name] = np.array(rows, dtype=DTYPES[vtype]).reshape(ntup, ncomp)
        i += 1 + ntup
    return blocks


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    errors = []
    for event in ("ErrorEvent", "WarningEvent"):
        reader.AddObserver(event, lambda obj, ev: errors.append(ev))
    reader.SetFileName(path)
    reader.Update()
    check(not errors and reader.GetErrorCode() == 0, f"{path}: the VTK reader reported {errors or 'an error'}")
    return reader.GetOutput()


def compare(name, got, want):
    check(got.dtype == want.dtype, f"{name}: type {got.dtype}, expected {want.dtype}")
    check(got.size == want.size, f"{name}: {got.size} values, expected {want.size}")
    got = got.reshape(want.shape)
    # Floats are compared by bit pattern: exact, and -0.0 differs from 0.0.
    bits = {8: np.uint64, 4: np.uint32, 1: np.uint8}[want.itemsize]
    differ = np.argwhere(got.view(bits) != want.view(bits))
    if len(differ):
        t, c = differ[0]
        g, w = got[t, c], want[t, c]
        hexes = f" ({float(g).hex()} vs {float(w).hex()})" if want.dtype.kind == "f" else ""
        raise Mismatch(f"{name}[{t}][{c}] = {g!r}, expected {w!r}{hexes}; {len(differ)} values differ")


def check_vtu(vtu, ref):
    want = read_reference(ref)
    grid = read_vtu(vtu)
    n = len(want["Points"])
    check(grid.GetNumberOfPoints() == n, f"{grid.GetNumberOfPoints()} points, expected {n}")
    check(grid.GetNumberOfCells() == n, f"{grid.GetNumberOfCells()} cells, expected {n}")
    if n:
        compare("Points", vtk_to_numpy(grid.GetPoints().GetData()), want["Points"])
        types = vtk_to_numpy(grid.GetCellTypesArray())
        check((types == vtk.VTK_VERTEX).all(), f"cell types {sorted(set(types))}, expected VTK_VERTEX only")
        cells = grid.GetCells()
        check((vtk_to_numpy(cells.GetOffsetsArray()) == np.arange(n + 1)).all(), "cell offsets are not 0..n")
        check((vtk_to_numpy(cells.GetConnectivityArray()) == np.arange(n)).all(), "cell i is not point i")

    data = grid.GetPointData()
    names = {data.GetArrayName(k) for k in range(data.GetNumberOfArrays())}
    expected = set(want) - {"Points"}
    check(names == expected, f"point data arrays {sorted(names)}, expected {sorted(expected)}")
    for name in sorted(expected):
        array = data.GetArray(name)
        ncomp = want[name].shape[1]
        check(array.GetNumberOfComponents() == ncomp,
              f"{name}: {array.GetNumberOfComponents()} components, expected {ncomp}")
        compare(name, vtk_to_numpy(array), want[name])


def check_pvd(pvd, ref):
    # VTK itself has no .pvd reader (vtkPVDReader is ParaView's), so the index is parsed as
    # XML and every frame it names is opened with VTK's reader.
    with open(ref) as f:
        want = [line.split() for line in f if line.strip() and not line.startswith("#")]
    root = ET.parse(pvd).getroot()
    check(root.tag == "VTKFile" and root.get("type") == "Collection", "root is not <VTKFile type=\"Collection\">")
    collection = root.find("Collection")
    check(collection is not None, "no <Collection> element")
    sets = collection.findall("DataSet")
    check(len(sets) == len(want), f"{len(sets)} data sets, expected {len(want)}")
    for k, (ds, (time, name, points)) in enumerate(zip(sets, want)):
        check(float(ds.get("timestep")) == float(time),
              f"data set {k}: timestep {ds.get('timestep')}, expected {time}")
        check(ds.get("file") == name, f"data set {k}: file {ds.get('file')}, expected {name}")
        grid = read_vtu(os.path.join(os.path.dirname(pvd), name))
        check(grid.GetNumberOfPoints() == int(points),
              f"{name}: {grid.GetNumberOfPoints()} points, expected {points}")


def main(argv):
    try:
        if len(argv) == 4 and argv[1] == "--pvd":
            check_pvd(argv[2], argv[3])
        elif len(argv) == 3:
            check_vtu(argv[1], argv[2])
        else:
            print(__doc__)
            return 2
    except Mismatch as e:
        print(f"vtk_readback: MISMATCH: {e}")
        return 1
    print("vtk_readback: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
