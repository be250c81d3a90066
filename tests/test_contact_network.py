"""The frames of a run read back with VTK's own readers (pytest, registered in CTest as
contact_network): the contact network adds up to each grain's contact force, every frame
carries its time, the walls are drawn where they are, Python started in the output folder
imports the real vtk module, and `tsubu export` gives a particle file a new run starts from.

Environment: TSUBU_BINARY (the tsubu executable), TSUBU_SOURCE_DIR (the repository).
"""
import csv
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import vtk
from vtk.util.numpy_support import vtk_to_numpy

TSUBU = os.environ["TSUBU_BINARY"]
SCENARIO = os.path.join(os.environ["TSUBU_SOURCE_DIR"], "tests", "scenarios", "contact_network.toml")
DENSITY = {0: 2500.0, 1: 7800.0}  # kg/m^3, the scenario's materials in order
GRAVITY = np.array([0.0, 0.0, -9.81])
LOWER, UPPER = np.array([0.0, 0.0, 0.0]), np.array([0.006, 0.006, 0.012])
LID_Z0, LID_SPEED = 0.012, -0.02  # wall 1: m, m/s until the end of the run


def run_tsubu(out, *sets):
    args = [TSUBU, "run", SCENARIO, "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    result = subprocess.run(args, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert result.returncode == 0, result.stderr
    return out


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    # Checkpoints at t = 0.05 s and at the end (0.1 s), for the export.
    return run_tsubu(tmp_path_factory.mktemp("contact_network") / "out", "output.checkpoint_every_steps=10000")


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader() if str(path).endswith(".vtu") else vtk.vtkXMLPolyDataReader()
    errors = []
    for event in ("ErrorEvent", "WarningEvent"):
        reader.AddObserver(event, lambda obj, ev: errors.append(ev))
    reader.SetFileName(str(path))
    reader.Update()
    assert not errors and reader.GetErrorCode() == 0, f"{path}: {errors}"
    return reader.GetOutput()


def index(path):
    """(time, file) of each data set of a .pvd."""
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.find("Collection").findall("DataSet")]


def arrays(data):
    return {data.GetArrayName(k): vtk_to_numpy(data.GetArray(k)) for k in range(data.GetNumberOfArrays())}


def test_every_frame_carries_its_time(out):
    frames = out / "frames"
    times = None
    for kind in ("particles", "contacts", "walls"):
        entries = index(frames / f"{kind}.pvd")
        assert len(entries) == 6  # t = 0, 0.02, ..., 0.1
        for time, name in entries:
            value = read(frames / name).GetFieldData().GetArray("TimeValue")
            assert value is not None, name
            assert value.GetValue(0) == time, name
        assert times is None or [t for t, _ in entries] == times
        times = [t for t, _ in entries]


def frame(out, k):
    grains = read(out / "frames" / f"frame_{k:05d}.vtu")
    network = read(out / "frames" / f"contacts_{k:05d}.vtp")
    return grains, network


def test_contact_forces_add_up_to_each_grains_contact_force(out):
    for k in range(6):
        grains, network = frame(out, k)
        g = arrays(grains.GetPointData())
        c = arrays(network.GetCellData())
        row = {pid: n for n, pid in enumerate(g["id"])}
        total = np.zeros((len(g["id"]), 3))
        force = c["normal_force"] + c["tangential_force"]
        for n in range(len(c["id_i"])):
            total[row[c["id_i"][n]]] += force[n]
            if c["id_j"][n] >= 0:
                total[row[c["id_j"][n]]] -= force[n]  # Newton's third law
        mass = np.array([DENSITY[m] for m in g["material"]]) * np.pi / 6 * g["diameter"] ** 3
        expected = g["force"] - mass[:, None] * GRAVITY  # no fluid: the rest is contact force
        scale = np.abs(g["force"]).max()
        assert np.abs(total - expected).max() <= 1e-12 * scale, f"frame {k}"
        if k == 5:  # the bed has settled on the floor: pairs and floor contacts
            assert (c["id_j"] >= 0).sum() > 50 and (c["wall"] == 0).sum() > 5
            assert set(c["wall"]) <= {-1, 0}  # the lid and the tilted wall touch nothing


def test_lines_run_from_each_centre_along_the_branch_vector(out):
    grains, network = frame(out, 5)
    g = arrays(grains.GetPointData())
    centre = {pid: x for pid, x in zip(g["id"], vtk_to_numpy(grains.GetPoints().GetData()))}
    radius = {pid: d / 2 for pid, d in zip(g["id"], g["diameter"])}
    c = arrays(network.GetCellData())
    points = vtk_to_numpy(network.GetPoints().GetData())
    velocity = {pid: v for pid, v in zip(g["id"], g["velocity"])}
    n = len(c["id_i"])
    assert network.GetNumberOfCells() == n and len(points) == 2 * n
    attractive = 0
    for k in range(n):
        i = c["id_i"][k]
        assert (points[2 * k] == centre[i]).all()
        assert np.allclose(points[2 * k + 1] - points[2 * k], c["branch"][k], rtol=0, atol=1e-15)
        b = c["branch"][k]
        unit = b / np.linalg.norm(b)
        if c["wall"][k] < 0:  # |b| = r_i + r_j - overlap; the point mid-overlap
            assert np.linalg.norm(b) == pytest.approx(radius[i] + radius[c["id_j"][k]] - c["overlap"][k], rel=1e-12)
            arm = radius[i] - c["overlap"][k] / 2
            assert np.allclose(c["contact_point"][k], centre[i] + arm * unit, rtol=0, atol=1e-15)
        else:  # the floor: the point on the plane below the centre
            assert c["contact_point"][k][2] == pytest.approx(0, abs=1e-18)
            assert np.linalg.norm(b) == pytest.approx(radius[i] - c["overlap"][k], rel=1e-9)
        fn, ft = c["normal_force"][k], c["tangential_force"][k]
        assert abs(np.dot(ft, unit)) <= 1e-9 * np.linalg.norm(fn)  # in the tangent plane
        assert np.linalg.norm(fn - np.dot(fn, unit) * unit) <= 1e-9 * np.linalg.norm(fn)  # along the normal
        # Repulsive (on i, away from j or the wall), unless the pair is separating: Hertz
        # with Tsuji's dashpot is not clamped, so the dashpot may then pull.
        v_j = velocity[c["id_j"][k]] if c["wall"][k] < 0 else np.zeros(3)
        separating = np.dot(v_j - velocity[i], unit) > 0
        assert np.dot(fn, unit) < 0 or separating, f"contact {k}: attractive while approaching"
        attractive += np.dot(fn, unit) >= 0
    assert np.abs(c["tangential_force"]).max() > 0  # friction is at work in the bed
    assert attractive <= n // 20  # a few separating pairs at most


def test_csv_rows_are_the_vtp_cells(out):
    _, network = frame(out, 5)
    c = arrays(network.GetCellData())
    with open(out / "frames" / "contacts_00005.csv") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[:4] == ["time[s]", "i", "j", "wall"] and "fnx[N]" in header and "overlap[m]" in header
    rows = rows[1:]
    assert len(rows) == len(c["id_i"])
    col = {name: k for k, name in enumerate(header)}
    for k, row in enumerate(rows):
        assert float(row[col["time[s]"]]) == index(out / "frames" / "contacts.pvd")[5][0]
        assert (int(row[col["i"]]), int(row[col["j"]]), int(row[col["wall"]])) == (c["id_i"][k], c["id_j"][k], c["wall"][k])
        for name, array in (("p", "contact_point"), ("b", "branch"), ("fn", "normal_force"), ("ft", "tangential_force")):
            unit = "[N]" if name.startswith("f") else "[m]"
            got = [float(row[col[name + axis + unit]]) for axis in "xyz"]
            assert got == list(c[array][k]), (k, name)
        assert float(row[col["overlap[m]"]]) == c["overlap"][k]
        assert [float(row[col[f"xi_{a}[m]"]]) for a in "xyz"] == list(c["tangential_spring"][k])


def wall_quads(path):
    walls = read(path)
    points = vtk_to_numpy(walls.GetPoints().GetData())
    assert walls.GetNumberOfCells() == 3
    return [points[4 * k:4 * k + 4] for k in range(3)], arrays(walls.GetCellData())


def test_walls_cover_the_domain_and_move_with_a_moving_wall(out):
    for time, name in index(out / "frames" / "walls.pvd"):
        quads, cells = wall_quads(out / "frames" / name)
        assert list(cells["wall"]) == [0, 1, 2]
        floor, lid, tilted = quads
        assert (floor[:, 2] == 0).all()
        assert np.allclose(lid[:, 2], LID_Z0 + LID_SPEED * time, rtol=0, atol=1e-12), time
        for quad in (floor, lid):  # the box face: x and y spanning the domain
            for axis in (0, 1):
                assert np.allclose(sorted(set(quad[:, axis])), [LOWER[axis], UPPER[axis]], rtol=0, atol=1e-15)
        assert time == 0 or (cells["velocity"][1] == [0, 0, LID_SPEED]).all()
        # The tilted wall: its corners on its plane, and the box seen along its normal inside it.
        normal = np.array([0.0, -1.0, -1.0]) / np.sqrt(2)
        assert np.allclose((tilted - [0, 0.006, 0.010]) @ normal, 0, atol=1e-15)
        edges = [tilted[(k + 1) % 4] - tilted[k] for k in range(4)]
        for corner in np.array(np.meshgrid(*zip(LOWER, UPPER))).T.reshape(-1, 3):
            for k in range(4):  # on the inner side of every edge (counter-clockwise about the normal)
                assert np.dot(np.cross(edges[k], corner - tilted[k]), normal) >= -1e-15


def test_the_frames_are_the_same_bytes_for_any_thread_count(out, tmp_path):
    threads = tmp_path / "threads"
    result = subprocess.run([TSUBU, "run", SCENARIO, "--out", str(threads), "--threads", "2"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    names = sorted(os.listdir(out / "frames"))
    assert names == sorted(os.listdir(threads / "frames"))
    for name in names:
        assert (out / "frames" / name).read_bytes() == (threads / "frames" / name).read_bytes(), name


def test_contacts_off_writes_no_network(tmp_path):
    out = run_tsubu(tmp_path / "out", "output.contacts=false", "simulation.duration=0.001")
    names = os.listdir(out / "frames")
    assert "particles.pvd" in names and "walls.pvd" in names
    assert not [n for n in names if n.startswith("contacts")]


def test_python_in_the_output_folder_imports_the_real_vtk(out):
    assert not (out / "vtk").exists()
    probe = "import vtk, os; print(os.path.realpath(vtk.__file__)); vtk.vtkXMLPolyDataReader()"
    result = subprocess.run([sys.executable, "-c", probe], cwd=out, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert not result.stdout.strip().startswith(os.path.realpath(out))


def export(out, *args):
    return subprocess.run([TSUBU, "export", str(out), *args], capture_output=True, text=True)


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in row] for row in rows[1:]])


def test_export_picks_the_checkpoint_at_or_before_the_time(out, tmp_path):
    result = export(out, "--at", "0.07", "--to", str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert "step 10000" in result.stdout
    assert (tmp_path / "particles_000000010000.csv").exists() and (tmp_path / "contacts_000000010000.csv").exists()
    result = export(out, "--at", "0.01", "--to", str(tmp_path))
    assert result.returncode == 2 and "no checkpoint at or before" in result.stderr, result.stderr


@pytest.mark.parametrize("time", ["nan", "inf", "-inf"])
def test_export_refuses_a_time_that_is_not_finite(out, tmp_path, time):
    """--at nan exported the newest checkpoint."""
    result = export(out, "--at", time, "--to", str(tmp_path))
    assert result.returncode == 2 and not any(tmp_path.iterdir())
    assert result.stderr == f"error: --at {time}: must be a time in seconds, a finite number\n"


def test_a_run_started_from_an_export_has_the_exported_particles(out, tmp_path):
    result = export(out)  # the newest: the end of the run
    assert result.returncode == 0, result.stderr
    particles = out / "export" / "particles_000000020000.csv"
    header, state = read_csv(particles)
    assert header == ["id", "material", "radius[m]", "x[m]", "y[m]", "z[m]", "vx[m/s]", "vy[m/s]", "vz[m/s]",
                      "wx[rad/s]", "wy[rad/s]", "wz[rad/s]"]
    assert (state[:, 0] == np.arange(len(state))).all() and set(state[:, 1]) == {0, 1}
    # The same box, materials and walls; the particles from the file.
    with open(SCENARIO) as f:
        text = f.read()
    text = text[:text.index("[[particles]]")] + f'[[particles]]\nsource = "file"\nfile = "{particles}"\n'
    scenario = tmp_path / "from_export.toml"
    scenario.write_text(text)
    args = [TSUBU, "run", str(scenario), "--out", str(tmp_path / "new"), "--set", "simulation.duration=5e-6"]
    result = subprocess.run(args, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    grains = read(tmp_path / "new" / "frames" / "frame_00000.vtu")
    g = arrays(grains.GetPointData())
    order = np.argsort(g["id"])  # the run sorts its particles in space: compare by id
    g = {name: values[order] for name, values in g.items()}
    assert (g["id"] == state[:, 0]).all() and (g["material"] == state[:, 1]).all()
    assert (g["diameter"] == 2 * state[:, 2]).all()
    assert (vtk_to_numpy(grains.GetPoints().GetData())[order] == state[:, 3:6]).all()
    assert (g["velocity"] == state[:, 6:9]).all() and (g["angular_velocity"] == state[:, 9:12]).all()
    # The exported contacts are those of the new run's first evaluation: the same pairs, the
    # same normal forces (its tangential springs start anew).
    _, exported = read_csv(out / "export" / "contacts_000000020000.csv")
    network = arrays(read(tmp_path / "new" / "frames" / "contacts_00000.vtp").GetCellData())
    def by_pair(ids, fn):  # a pair is listed either way round: key it by (smaller id, larger id)
        out = {}
        for i, j, w, f in zip(*ids, fn):
            swap = j >= 0 and j < i
            out[(int(j), int(i), int(w)) if swap else (int(i), int(j), int(w))] = -f if swap else f
        return out
    want = by_pair((exported[:, 1], exported[:, 2], exported[:, 3]), exported[:, 10:13])
    got = by_pair((network["id_i"], network["id_j"], network["wall"]), network["normal_force"])
    assert len(want) > 50 and want.keys() == got.keys()
    for key, f in want.items():
        assert np.allclose(got[key], f, rtol=1e-12, atol=0), key
