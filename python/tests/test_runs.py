"""tsubu.runs: reading run folders that tsubu writes (a small inflow run, about a second)."""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np
import pytest

from tsubu.runs import RunError, read_dataset, read_run, read_table

ROOT = Path(__file__).resolve().parents[2]
TSUBU = os.environ.get("TSUBU_BINARY", str(ROOT / "build" / "tsubu"))

try:
    import vtkmodules.vtkIOXML  # noqa: F401
    HAVE_VTK = True
except ImportError:
    HAVE_VTK = False


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """tests/scenarios/inflow_small.toml to t = 0.2 s: 41 series rows, 5 frames, tracks of 0, 7, 40."""
    out = tmp_path_factory.mktemp("runs") / "inflow"
    subprocess.run([TSUBU, "run", str(ROOT / "tests/scenarios/inflow_small.toml"), "--out", str(out),
                    "--set", "simulation.duration=0.2"], check=True, capture_output=True)
    return out


def test_summary_and_series(run_dir):
    run = read_run(run_dir)
    summary = json.loads((run_dir / "run.json").read_text())
    assert run.summary == summary and run.status == "ok" and run.results == summary["results"]
    assert run.run_id == (run_dir / ".tsubu-run").read_text().strip() == summary["run_id"]
    with open(run_dir / "series.csv") as f:
        rows = list(csv.reader(f))
    assert list(run.series.dtype.names) == rows[0]
    assert len(run.series) == len(rows) - 1 == 41
    for k, name in enumerate(rows[0]):  # every value as the file has it, integers as int64
        want = [float(r[k]) for r in rows[1:]]
        assert run.series[name].tolist() == want, name
    assert run.series["contacts"].dtype == np.int64 and run.series["time"].dtype == np.float64
    assert run.series["time"][-1] == pytest.approx(0.2)
    assert run.series["particles"][-1] == summary["particles"]
    assert run.series["porosity"][-1] == pytest.approx(summary["results"]["porosity"], rel=1e-11)


def test_tracks(run_dir):
    run = read_run(run_dir)
    assert run.track.dtype.names[:5] == ("time", "id", "x", "y", "z")
    assert set(run.tracks) <= {0, 7, 40} and 0 in run.tracks
    assert sum(len(t) for t in run.tracks.values()) == len(run.track)
    for pid, rows in run.tracks.items():
        assert (rows["id"] == pid).all() and (np.diff(rows["time"]) > 0).all()


def test_frames(run_dir):
    run = read_run(run_dir)
    assert run.frames is run.collections["particles"] and run.frames.path.parent.parent == run_dir
    assert run.frames.times.tolist() == pytest.approx([0, 0.05, 0.1, 0.15, 0.2])
    assert [f.name for f in run.frames.files] == [f"frame_{k:05d}.vtu" for k in range(5)]
    first, last = run.frame(0), run.frame(-1)
    assert len(first) == 0 and first["velocity"].shape == (0, 3)
    assert last.time == run.frames.times[-1] and len(last) == run.summary["particles"]
    assert last.points.shape == (len(last), 3) and last["position"] is last.points
    assert len(set(last["id"].tolist())) == len(last) and (last["diameter"] == 0.004).all()
    lo, hi = np.array(run.summary["domain"]["lower"]), np.array(run.summary["domain"]["upper"])
    assert ((last.points >= lo) & (last.points <= hi)).all()
    with pytest.raises(KeyError, match="no array 'pressure'"):
        last["pressure"]
    assert len(run.contact_frame(0)) == 0 and "walls" in run.collections  # no grains yet at t = 0


def test_a_run_without_a_contact_network(run_dir, tmp_path):
    copy = tmp_path / "run"
    shutil.copytree(run_dir, copy)
    (next(copy.rglob("contacts.pvd"))).unlink()
    with pytest.raises(RunError, match="no contacts.pvd"):
        read_run(copy).contact_frame(0)


@pytest.mark.skipif(not HAVE_VTK, reason="the vtk module (python3-vtk9) is not importable")
def test_builtin_reader_matches_vtk(run_dir):
    run = read_run(run_dir)
    for path in run.frames.files:
        with_vtk, builtin = read_dataset(path, use_vtk=True), read_dataset(path, use_vtk=False)
        assert with_vtk.keys() == builtin.keys()
        for name in ["points", *with_vtk.keys()]:
            a, b = with_vtk[name], builtin[name]
            assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes(), name


CONTACTS_VTP = """<?xml version="1.0"?>
<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
<PolyData>
<FieldData><DataArray type="Float64" Name="TimeValue" NumberOfTuples="1" format="ascii">0.25</DataArray></FieldData>
<Piece NumberOfPoints="4" NumberOfLines="2">
<Points><DataArray type="Float64" Name="position" NumberOfComponents="3" format="ascii">
0 0 0 0 0 1 1 1 1 1 1 0</DataArray></Points>
<Lines>
<DataArray type="Int64" Name="connectivity" NumberOfComponents="1" format="ascii">0 1 2 3</DataArray>
<DataArray type="Int64" Name="offsets" NumberOfComponents="1" format="ascii">2 4</DataArray>
</Lines>
<CellData>
<DataArray type="Int64" Name="id_i" NumberOfComponents="1" format="ascii">3 5</DataArray>
<DataArray type="Float64" Name="normal_force" NumberOfComponents="3" format="ascii">0 0 1.5 0 0 -2</DataArray>
</CellData>
</Piece>
</PolyData>
</VTKFile>
"""


def test_any_frames_folder_and_contact_files(run_dir, tmp_path):
    """The frames are found through their .pvd files, whatever the folder; a contacts
    collection gives contact frames and the .csv tables beside them."""
    moved = tmp_path / "run"
    shutil.copytree(run_dir, moved)
    frames = moved / "some" / "where"
    frames.parent.mkdir()
    (moved / read_run(run_dir).frames.path.parent.name).rename(frames)
    for stale in frames.glob("contacts*"):  # those of tsubu, if it wrote any
        stale.unlink()
    (frames / "contacts_00000.vtp").write_text(CONTACTS_VTP)
    (frames / "contacts_00000.csv").write_text("time[s],i,j,wall,fnz[N]\n0.25,3,-1,0,1.5\n0.25,5,3,-1,-2\n")
    (frames / "contacts.pvd").write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="1.0">\n<Collection>\n'
        '<DataSet timestep="0.25" file="contacts_00000.vtp"/>\n</Collection>\n</VTKFile>\n')
    run = read_run(moved)
    assert {"contacts", "particles"} <= set(run.collections) and run.frames.path.parent == frames
    assert run.frame(-1).points.tobytes() == read_run(run_dir).frame(-1).points.tobytes()
    for use_vtk in [False] + [True] * HAVE_VTK:
        network = read_run(moved, use_vtk=use_vtk).contact_frame(0)
        assert network.time == 0.25 and network["TimeValue"].tolist() == [0.25]
        assert network["id_i"].tolist() == [3, 5] and network["normal_force"][:, 2].tolist() == [1.5, -2]
        assert network.points.shape == (4, 3)
    table = run.contact_table(0)
    assert table.dtype.names == ("time", "i", "j", "wall", "fnz")
    assert table["j"].tolist() == [-1, 3] and table["fnz"].tolist() == [1.5, -2.0]


@pytest.mark.skipif(not HAVE_VTK, reason="the vtk module (python3-vtk9) is not importable")
@pytest.mark.parametrize("header", ["UInt32", "UInt64"])
def test_builtin_reader_reads_vtk_binary(tmp_path, header):
    """Files written by VTK's own writer (inline base64, uncompressed) read the same both ways."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    rng = np.random.default_rng(1)
    data, points = vtkPolyData(), vtkPoints()
    points.SetData(numpy_to_vtk(rng.random((7, 3)), deep=True))
    data.SetPoints(points)
    for name, values in {"mass": rng.random(7), "count": np.arange(7, dtype=np.int32),
                         "spin": rng.random((7, 3))}.items():
        array = numpy_to_vtk(values, deep=True)
        array.SetName(name)
        data.GetPointData().AddArray(array)
    writer = vtkXMLPolyDataWriter()
    writer.SetInputData(data)
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToNone()
    getattr(writer, f"SetHeaderTypeTo{header}")()
    writer.SetFileName(str(tmp_path / "d.vtp"))
    assert writer.Write() == 1
    a, b = read_dataset(tmp_path / "d.vtp", use_vtk=True), read_dataset(tmp_path / "d.vtp", use_vtk=False)
    for name in ["points", "mass", "count", "spin"]:
        assert a[name].dtype == b[name].dtype and a[name].tobytes() == b[name].tobytes(), name


def test_killed_run_without_summary(run_dir, tmp_path):
    """A run under way or killed has no run.json yet: the rest still reads."""
    copy = tmp_path / "run"
    shutil.copytree(run_dir, copy)
    (copy / "run.json").unlink()
    run = read_run(copy)
    assert run.summary is None and run.status is None and run.results == {}
    assert len(run.series) == 41 and len(run.frames) == 5


def test_a_run_running_again_is_running(tmp_path):
    """A run resumed after an interruption read as "interrupted" (run.json's status) while it ran."""
    out = tmp_path / "run"
    sets = {"simulation.duration": 0.001, "simulation.dt": 1e-6, "output.vtk_interval": 0,
            "output.series_interval": 1000, "output.checkpoint_every_steps": 200}  # no rows while it runs
    subprocess.run([TSUBU, "run", str(ROOT / "tests/scenarios/inflow_small.toml"), "--out", str(out),
                    *(a for k, v in sets.items() for a in ("--set", f"{k}={v}"))], check=True, capture_output=True)
    assert read_run(out).status == "ok"
    resumed = subprocess.Popen([TSUBU, "resume", str(out), "--set", "simulation.duration=100"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        end = time.monotonic() + 60
        while read_run(out).status != "running":
            assert resumed.poll() is None and time.monotonic() < end, "the resume never held its folder"
            time.sleep(0.01)
        assert read_run(out).summary["status"] == "ok"  # the earlier session's
        while not any(int(f.stem[5:]) > 1000 for f in (out / "checkpoint").glob("step_*.tsbk")):
            assert resumed.poll() is None and time.monotonic() < end, "the resume never stepped"
            time.sleep(0.01)  # stepping: SIGINT then stops it with a checkpoint
    finally:
        resumed.send_signal(signal.SIGINT)
        assert resumed.wait() == 4
    assert read_run(out).status == "interrupted"


def test_not_a_run(tmp_path):
    with pytest.raises(RunError, match="no such folder"):
        read_run(tmp_path / "missing")
    with pytest.raises(RunError, match=r"not a tsubu run folder \(it has neither run.json nor .tsubu-run\)"):
        read_run(tmp_path)
    (tmp_path / "run.json").write_text("{ cut short")
    with pytest.raises(RunError, match="run.json: cannot read the run summary"):
        read_run(tmp_path)


def test_bad_tables(tmp_path):
    (tmp_path / "a.csv").write_text("time,contacts\n0,1\n0.5\n")
    with pytest.raises(RunError, match=r"a.csv:3: 1 values, expected 2"):
        read_table(tmp_path / "a.csv")
    (tmp_path / "b.csv").write_text("time,contacts\n0,1\n0.5,many\n")
    with pytest.raises(RunError, match=r"b.csv:3: contacts: 'many' is not a number"):
        read_table(tmp_path / "b.csv", numbers_only=True)
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / ".tsubu-run").write_text("1\n")
    shutil.copy(tmp_path / "b.csv", tmp_path / "x" / "series.csv")
    with pytest.raises(RunError, match=r"series.csv:3: contacts: 'many' is not a number"):
        read_run(tmp_path / "x")
    (tmp_path / "c.csv").write_text("time,x\n")
    empty = read_table(tmp_path / "c.csv")
    assert len(empty) == 0 and empty.dtype.names == ("time", "x")


def test_tables_with_text_and_empty_cells(tmp_path):
    """Any CSV file reads (a sweep's results.csv, with its text case column, was refused)."""
    (tmp_path / "r.csv").write_text("case,status,steps,porosity,message\nseed=3,ok,20000,0.41,\n"
                                     "seed=4,pending,,,\"a, b\"\n")
    table = read_table(tmp_path / "r.csv")
    assert table["case"].tolist() == ["seed=3", "seed=4"] and table["status"].tolist() == ["ok", "pending"]
    assert table["steps"][0] == 20000 and np.isnan(table["steps"][1]) and np.isnan(table["porosity"][1])
    assert table["porosity"][0] == 0.41 and table["message"].tolist() == ["", "a, b"]


def test_dataframes(run_dir, monkeypatch):
    """dataframes=True hands every table to pandas.DataFrame; without pandas it is refused."""
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas fails
    with pytest.raises(RunError, match="dataframes=True needs pandas"):
        read_run(run_dir, dataframes=True)

    class DataFrame:
        def __init__(self, table):
            self.table = table

    monkeypatch.setitem(sys.modules, "pandas", types.SimpleNamespace(DataFrame=DataFrame))
    run = read_run(run_dir, dataframes=True)
    assert isinstance(run.series, DataFrame) and run.series.table.tobytes() == read_run(run_dir).series.tobytes()
    assert isinstance(run.track, DataFrame)


def test_outflow(run_dir, tmp_path):
    """A box with an open face (tests/scenarios/chute_open.toml): run.outflow holds the grains
    gone through it, as many as series.csv and run.json count, and None for a closed box."""
    out = tmp_path / "chute"
    subprocess.run([TSUBU, "run", str(ROOT / "tests/scenarios/chute_open.toml"), "--out", str(out),
                    "--set", "simulation.duration=0.1"], check=True, capture_output=True)
    run = read_run(out)
    assert len(run.outflow) > 0
    assert set(run.outflow["face"]) == {"x_max"}
    assert np.all(run.outflow["x"] > 0.04) and np.all(np.diff(run.outflow["time"]) >= 0)
    assert run.series["outflow_count"][-1] == len(run.outflow) == run.results["outflow_count"]
    assert run.series["outflow_mass"][-1] == pytest.approx(run.outflow["mass"].sum(), rel=1e-12)
    assert read_run(run_dir).outflow is None
