"""Reading a tsubu run folder: its summary, time series, tracks and frames.

    run = tsubu.runs.read_run("out/settle-poly")
    run.summary["status"], run.results["porosity"]    # run.json
    run.series["time"], run.series["contacts"]        # series.csv, a NumPy structured array
    run.tracks[7]["z"]                                # track.csv rows of particle 7
    run.outflow["id"], run.outflow["time"]            # outflow.csv: grains gone through open faces
    run.frames.times, run.frame(-1)["diameter"]       # the particle frames (.pvd, .vtu)

The frames are found through the .pvd collections anywhere in the folder (whatever the
subfolder is called): each one is a `Collection` named after its file (`particles`,
`contacts`, ...). A frame is read with VTK's own readers when the `vtk` module (Debian's
python3-vtk9) is importable, else by the small reader below, which knows the XML files tsubu
writes (inline data, base64 or ascii, uncompressed). Tables (series.csv, track.csv and a
frame's .csv beside its .vtp) become NumPy structured arrays: a column whose every value is
an integer is int64, one of numbers (empty cells are NaN) float64, any other text (a sweep's
results.csv), and a unit in the header (`time[s]`) is dropped from the field name. With `dataframes=True` they are pandas DataFrames instead. Format of the
files: docs/cli.md (output folder); this module: docs/sweeps.md (reading a run).
"""
import base64
import csv
import fcntl
import json
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

__all__ = ["RunError", "Run", "Collection", "Dataset", "read_run", "read_table", "read_dataset", "lock_holder"]

RUN_LOCK = ".tsubu-lock"  # in a run's folder, held by the tsubu running there (io/output_dir.hpp)


class RunError(ValueError):
    """A folder that is not a run, or a file of it that cannot be read; the message names it."""


_INTEGER = re.compile(r"-?[0-9]+\Z")
_UNIT = re.compile(r"\[[^\]]*\]\Z")


def lock_holder(folder):
    """Who holds the run folder's lock ("pid P on HOST, since T", as tsubu writes it) while a
    tsubu runs or resumes there, else None."""
    try:
        fd = os.open(Path(folder) / RUN_LOCK, os.O_RDONLY)
    except FileNotFoundError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        return None
    except BlockingIOError:
        return (Path(folder) / RUN_LOCK).read_text(errors="replace").strip() or "holder unknown"
    finally:
        os.close(fd)  # releases the shared lock at once


def read_table(path, numbers_only=False):
    """A CSV file with a header row as a NumPy structured array (one field per column): int64
    where every value is an integer, float64 where every value is a number or empty (NaN),
    text otherwise. numbers_only: a value that is not a number is a RunError instead (the
    files tsubu writes hold numbers only)."""
    path = Path(path)
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise RunError(f"{path}: cannot read: {e.strerror}") from None
    if not rows:
        raise RunError(f"{path}: empty file, expected a header row")
    names = [_UNIT.sub("", name.strip()) for name in rows[0]]
    if len(set(names)) != len(names):
        raise RunError(f"{path}:1: the header names a column twice: {','.join(rows[0])}")
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(names):
            raise RunError(f"{path}:{line}: {len(row)} values, expected {len(names)} (the header's columns)")
    columns = list(zip(*rows[1:])) if len(rows) > 1 else [()] * len(names)
    fields = []
    for name, column in zip(names, columns):
        integer = bool(column) and all(_INTEGER.match(v) for v in column)
        text = next(((k, v) for k, v in enumerate(column, start=2) if v.strip() and not _is_number(v)), None)
        if text and numbers_only:
            raise RunError(f"{path}:{text[0]}: {name}: {text[1]!r} is not a number")
        if integer:
            fields.append(np.array(column, dtype=str).astype(np.int64))
        elif text:
            fields.append(np.array(column, dtype=str))
        else:
            fields.append(np.array([v if v.strip() else "nan" for v in column], dtype=str).astype(np.float64))
    table = np.empty(len(rows) - 1, dtype=[(name, field.dtype) for name, field in zip(names, fields)])
    for name, field in zip(names, fields):
        table[name] = field
    return table


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


class Dataset:
    """One frame file: its points, and its arrays per point, per cell and for the whole set.

    `dataset[name]` looks the name up among the point, cell and field arrays, in that order;
    `points` (also `dataset["position"]`) is an (N, 3) array. Vectors are (N, 3) arrays,
    scalars (N,) arrays, of the file's types."""

    def __init__(self, path, time, points, point_data, cell_data, field_data):
        self.path, self.time, self.points = Path(path), time, points
        self.point_data, self.cell_data, self.field_data = point_data, cell_data, field_data

    def __getitem__(self, name):
        for arrays in (self.point_data, self.cell_data, self.field_data):
            if name in arrays:
                return arrays[name]
        if name in ("points", "position"):
            return self.points
        raise KeyError(f"{self.path}: no array {name!r} (it has {', '.join(self.keys())})")

    def keys(self):
        return [*self.point_data, *self.cell_data, *self.field_data]

    def __len__(self):
        return len(self.points)

    def __repr__(self):
        return f"Dataset({str(self.path)!r}, time={self.time}, points={len(self)}, arrays={self.keys()})"


_VTK_TYPES = {"Int8": np.int8, "UInt8": np.uint8, "Int16": np.int16, "UInt16": np.uint16, "Int32": np.int32,
              "UInt32": np.uint32, "Int64": np.int64, "UInt64": np.uint64, "Float32": np.float32,
              "Float64": np.float64}


def _shaped(values, components):
    return values.reshape(-1, components) if components > 1 else values.reshape(-1)


def _parse_data_array(path, element, endian, header_type):
    """The values of one inline <DataArray> (ascii or uncompressed base64 binary)."""
    name = element.get("Name", "")
    vtk_type = element.get("type")
    if vtk_type not in _VTK_TYPES:
        raise RunError(f"{path}: DataArray {name!r}: type {vtk_type!r} is not one of {', '.join(_VTK_TYPES)}")
    dtype = np.dtype(_VTK_TYPES[vtk_type]).newbyteorder(endian)
    components = int(element.get("NumberOfComponents", "1"))
    text = "".join((element.text or "").split())
    encoding = element.get("format", "ascii")
    if encoding == "ascii":
        values = np.array((element.text or "").split(), dtype=str).astype(dtype)
    elif encoding == "binary":
        # A header (the byte count) and the data, base64 encoded apart, or together as one block.
        header = np.dtype(header_type).newbyteorder(endian)
        head_chars = -(-header.itemsize // 3) * 4
        count = int(np.frombuffer(base64.b64decode(text[:head_chars]), header, 1)[0])
        raw = base64.b64decode(text[head_chars:]) if len(text) > head_chars else b""
        if len(raw) != count:
            raw = base64.b64decode(text)[header.itemsize:header.itemsize + count]
        if len(raw) != count or count % dtype.itemsize:
            raise RunError(f"{path}: DataArray {name!r}: {len(raw)} bytes of data, the header says {count}")
        values = np.frombuffer(raw, dtype).copy()
    else:
        raise RunError(f"{path}: DataArray {name!r}: format {encoding!r} needs the vtk module (python3-vtk9)")
    return _shaped(values.astype(dtype.newbyteorder("=")), components)


def _read_with_python(path):
    root = ET.parse(path).getroot()
    if root.get("compressor"):
        raise RunError(f"{path}: compressed data needs the vtk module (python3-vtk9)")
    kind = root.get("type")
    endian = "<" if root.get("byte_order", "LittleEndian") == "LittleEndian" else ">"
    header_type = _VTK_TYPES[root.get("header_type", "UInt32")]
    data_set = root.find(kind or "")
    pieces = data_set.findall("Piece") if data_set is not None else []
    if len(pieces) != 1:
        raise RunError(f"{path}: expected one <Piece> of a {kind} data set, found {len(pieces)}")

    def arrays(parent):
        if parent is None:
            return {}
        return {a.get("Name"): _parse_data_array(path, a, endian, header_type) for a in parent.findall("DataArray")}

    points = next(iter(arrays(pieces[0].find("Points")).values()), np.zeros((0, 3)))
    piece = pieces[0]
    return points, arrays(piece.find("PointData")), arrays(piece.find("CellData")), arrays(data_set.find("FieldData"))


def _vtk_reader(path):
    """VTK's reader for the file's kind, or None when the vtk module is not importable."""
    try:
        from vtkmodules import vtkIOXML
    except ImportError:
        return None
    kinds = {".vtu": vtkIOXML.vtkXMLUnstructuredGridReader, ".vtp": vtkIOXML.vtkXMLPolyDataReader}
    if path.suffix not in kinds:
        raise RunError(f"{path}: a frame must be a .vtu or .vtp file")
    return kinds[path.suffix]()


def _read_with_vtk(path, reader):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    errors = []
    for event in ("ErrorEvent", "WarningEvent"):
        reader.AddObserver(event, lambda obj, ev: errors.append(ev))
    reader.SetFileName(str(path))
    reader.Update()
    if errors or reader.GetErrorCode():
        raise RunError(f"{path}: VTK's reader reported {errors or 'an error'}")
    data = reader.GetOutput()

    def arrays(attributes):
        out = {}
        for k in range(attributes.GetNumberOfArrays()):
            a = attributes.GetAbstractArray(k)
            out[a.GetName()] = _shaped(vtk_to_numpy(a).copy(), a.GetNumberOfComponents())
        return out

    points = data.GetPoints()
    points = vtk_to_numpy(points.GetData()).reshape(-1, 3).copy() if points is not None else np.zeros((0, 3))
    return points, arrays(data.GetPointData()), arrays(data.GetCellData()), arrays(data.GetFieldData())


def read_dataset(path, time=None, use_vtk=None):
    """One .vtu or .vtp file as a Dataset. use_vtk: None reads with VTK when it is importable,
    True requires it, False always uses the built-in reader."""
    path = Path(path)
    if not path.is_file():
        raise RunError(f"{path}: no such frame file")
    reader = _vtk_reader(path) if use_vtk is not False else None
    if use_vtk and reader is None:
        raise RunError(f"{path}: use_vtk=True but the vtk module (python3-vtk9) cannot be imported")
    try:
        parts = _read_with_vtk(path, reader) if reader is not None else _read_with_python(path)
    except ET.ParseError as e:
        raise RunError(f"{path}: not a VTK XML file: {e}") from None
    return Dataset(path, time, *parts)


class Collection:
    """The frames one .pvd file indexes: `times` (s) and `files`, in the file's order."""

    def __init__(self, pvd, use_vtk=None, dataframes=False):
        self.path, self.name = Path(pvd), Path(pvd).stem
        self._use_vtk, self._dataframes = use_vtk, dataframes
        try:
            root = ET.parse(self.path).getroot()
        except ET.ParseError as e:
            raise RunError(f"{self.path}: not a .pvd collection: {e}") from None
        sets = root.findall("Collection/DataSet") if root.get("type") == "Collection" else None
        if sets is None:
            raise RunError(f"{self.path}: not a .pvd collection (no <VTKFile type=\"Collection\">)")
        try:
            self.times = np.array([float(s.get("timestep")) for s in sets])
        except (TypeError, ValueError):
            raise RunError(f"{self.path}: a DataSet without a numeric timestep") from None
        self.files = [self.path.parent / s.get("file", "") for s in sets]

    def __len__(self):
        return len(self.files)

    def read(self, i):
        """Frame i (negative counts from the end) as a Dataset."""
        return read_dataset(self.files[i], float(self.times[i]), self._use_vtk)

    def table(self, i):
        """The .csv file beside frame i's file (same name), as a table; None if there is none."""
        csv_path = self.files[i].with_suffix(".csv")
        return _as_frame(read_table(csv_path, numbers_only=True), self._dataframes) if csv_path.is_file() else None

    def __repr__(self):
        return f"Collection({self.name!r}, {len(self)} frames, {str(self.path)!r})"


def _as_frame(table, dataframes):
    if not dataframes or table is None:
        return table
    import pandas

    return pandas.DataFrame(table)


class Run:
    """A run folder as read by read_run()."""

    def __init__(self, path, dataframes=False, use_vtk=None):
        self.path = Path(path)
        if not self.path.is_dir():
            raise RunError(f"{self.path}: no such folder")
        summary, marker = self.path / "run.json", self.path / ".tsubu-run"
        if not summary.is_file() and not marker.is_file():
            raise RunError(f"{self.path}: not a tsubu run folder (it has neither run.json nor .tsubu-run)")
        if dataframes:
            try:
                import pandas  # noqa: F401
            except ImportError:
                raise RunError("dataframes=True needs pandas, which cannot be imported") from None
        self.summary = None  # None while a run is under way or after it was killed
        if summary.is_file():
            try:
                self.summary = json.loads(summary.read_text())
            except (OSError, ValueError) as e:
                raise RunError(f"{summary}: cannot read the run summary: {e}") from None
        self.run_id = marker.read_text().strip() if marker.is_file() else self.summary.get("run_id")

        def table(name):
            path = self.path / name
            return read_table(path, numbers_only=True) if path.is_file() else None

        series, track = table("series.csv"), table("track.csv")
        tracks = {} if track is None else {int(i): track[track["id"] == i] for i in np.unique(track["id"])}
        self.series, self.track = _as_frame(series, dataframes), _as_frame(track, dataframes)
        self.tracks = {i: _as_frame(rows, dataframes) for i, rows in tracks.items()}
        # outflow.csv (a box with open faces): numbers, and the face's name as text.
        outflow = self.path / "outflow.csv"
        self.outflow = _as_frame(read_table(outflow), dataframes) if outflow.is_file() else None
        self.collections = {}
        for pvd in sorted(p for p in self.path.rglob("*.pvd") if "checkpoint" not in p.relative_to(self.path).parts):
            collection = Collection(pvd, use_vtk, dataframes)
            if collection.name in self.collections:
                raise RunError(f"{pvd}: a second collection named {collection.name!r} "
                               f"(the first is {self.collections[collection.name].path})")
            self.collections[collection.name] = collection

    @property
    def status(self):
        """"running" while a tsubu runs or resumes in the folder (its lock is held), else
        run.json's status ("ok", "failed", "interrupted"), or None without run.json."""
        if lock_holder(self.path):
            return "running"
        return self.summary.get("status") if self.summary else None

    @property
    def results(self):
        """run.json's results: the analyses' final values and the inflow's rates and counts."""
        return self.summary.get("results", {}) if self.summary else {}

    @property
    def frames(self):
        """The particle frames (the collection `particles`), or None when the run wrote none."""
        return self.collections.get("particles")

    @property
    def contacts(self):
        """The contact-network frames (the collection `contacts`), or None."""
        return self.collections.get("contacts")

    def frame(self, i):
        """The particles of frame i (negative counts from the end): `points` (centres) and the
        arrays per particle (id, diameter, velocity, ...)."""
        return self._collection("particles").read(i)

    def contact_frame(self, i):
        """The contact network of frame i as written to its .vtp file."""
        return self._collection("contacts").read(i)

    def contact_table(self, i):
        """The contacts of frame i from the .csv beside its .vtp; None if there is none."""
        return self._collection("contacts").table(i)

    def _collection(self, name):
        if name not in self.collections:
            raise RunError(f"{self.path}: no {name}.pvd in the run folder (collections: "
                           f"{', '.join(self.collections) or 'none'})")
        return self.collections[name]

    def __repr__(self):
        return f"Run({str(self.path)!r}, status={self.status!r}, collections={list(self.collections)})"


def read_run(path, dataframes=False, use_vtk=None):
    """Reads the run folder `path` (written by `tsubu run` or `tsubu resume`).

    dataframes: tables as pandas DataFrames (RunError when pandas cannot be imported).
    use_vtk: None reads frames with VTK when it is importable, True requires it, False uses
    the built-in reader. Raises RunError, naming the folder or file, for a folder that is not a
    run or a file that cannot be read."""
    return Run(path, dataframes, use_vtk)
