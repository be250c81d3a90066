#!/usr/bin/env python3
"""Mesh walls against the plane: a ball rebounds off a flat mesh of many triangles at faces,
edges and vertices and at angles from 0 to 85 degrees, rolls across the mesh's shared edges,
and grazes a ridge and an apex; tsubu's runs on the mesh against the same runs on the plane
(and, where LIGGGHTS is installed, LIGGGHTS's on the same mesh against its plane). Writes
docs/validation/mesh-walls.png and mesh-walls.csv.

    /usr/bin/python3 validation/mesh_walls.py [--tsubu build/tsubu] [--liggghts liggghts] [--out docs/validation]
"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from report_files import save  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
R = 0.003          # m, the ball's radius
H = 0.002          # m, the side of the plate's square cells (two triangles each)
SPIN = (5.0, -3.0, 2.0)  # rad/s, the ball's spin before the impact
# Where the ball first touches the plate, in cells from a vertex shared by 8 triangles.
POINTS = [("face", 0.3, 0.2), ("edge", 0.5, 0.0), ("diagonal", 0.5, 0.5), ("vertex of 8", 0.0, 0.0),
          ("vertex of 4", 1.0, 0.0)]
ANGLES = [0, 15, 30, 45, 60, 75, 85]  # degrees from the normal
INTEGRATORS = [("velocity_verlet", 1e-6), ("block_hermite", 1e-4)]
# The plate in the plane z = 0 (a coordinate plane: the plane's bits) and tilted by 25 degrees
# about (1, 2, 0.5) with everything else turned alike (round-off).
TILT_AXIS, TILT_DEGREES = (1.0, 2.0, 0.5), 25.0


def turn(p, degrees):
    """p turned about TILT_AXIS by `degrees` (Rodrigues' formula), right-handed."""
    if degrees == 0:
        return tuple(p)
    size = math.sqrt(sum(c * c for c in TILT_AXIS))
    k = [c / size for c in TILT_AXIS]
    a = math.radians(degrees)
    kxp = (k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0])
    kp = sum(k[i] * p[i] for i in range(3))
    return tuple(p[i] * math.cos(a) + kxp[i] * math.sin(a) + k[i] * kp * (1 - math.cos(a)) for i in range(3))


def plate_triangles(n, h):
    """A square plate in z = 0 of n x n cells of side h centred on the origin, each cut into
    two triangles along alternating diagonals (vertices shared by 4 or 8 triangles)."""
    half = 0.5 * n * h
    v = lambda i, j: (i * h - half, j * h - half, 0.0)  # noqa: E731
    out = []
    for j in range(n):
        for i in range(n):
            if (i + j) % 2 == 0:
                out += [(v(i, j), v(i + 1, j), v(i + 1, j + 1)), (v(i, j), v(i + 1, j + 1), v(i, j + 1))]
            else:
                out += [(v(i, j), v(i + 1, j), v(i, j + 1)), (v(i + 1, j), v(i + 1, j + 1), v(i, j + 1))]
    return out


def ridge_triangles():
    """A roof of two faces sloping down at 20 degrees from a ridge along y: a convex edge."""
    s = -math.tan(math.radians(20)) * 0.01
    p = [(0, -0.01, 0), (0, 0.01, 0), (0.01, -0.01, s), (0.01, 0.01, s), (-0.01, -0.01, s), (-0.01, 0.01, s)]
    return [(p[a], p[b], p[c]) for a, b, c in [(0, 2, 3), (0, 3, 1), (0, 1, 5), (0, 5, 4)]]


def apex_triangles():
    """A pyramid's apex at the origin, its four faces sloping down at 20 degrees: convex edges
    and a convex corner."""
    s = -math.tan(math.radians(20)) * 0.01
    p = [(0, 0, 0), (0.01, -0.01, s), (0.01, 0.01, s), (-0.01, 0.01, s), (-0.01, -0.01, s)]
    return [(p[a], p[b], p[c]) for a, b, c in [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 1)]]


def write_stl(path, triangles):
    """An ASCII STL in metres, each facet's normal from its vertices' order."""
    with open(path, "w") as f:
        f.write("solid plate\n")
        for a, b, c in triangles:
            u = [b[k] - a[k] for k in range(3)]
            w = [c[k] - a[k] for k in range(3)]
            n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
            size = math.sqrt(sum(x * x for x in n))
            f.write("facet normal %r %r %r\n outer loop\n" % tuple(x / size for x in n))
            for p in (a, b, c):
                f.write("  vertex %r %r %r\n" % p)
            f.write(" endloop\nendfacet\n")
        f.write("endsolid plate\n")


def scenario(wall, x, v, w, *, duration, dt, integrator, gravity, restitution, tangential, track_interval):
    """A scenario of one glass ball (d = 6 mm) from x at velocity v and spin w against `wall`
    (a [[walls]] table's lines), tracked every track_interval."""
    law = f'tangential = "{tangential}"\nfriction = 0.5' if tangential != "none" else 'tangential = "none"'
    return f"""[simulation]
duration = {duration!r}
dt = {dt!r}
integrator = "{integrator}"
gravity = [{gravity[0]!r}, {gravity[1]!r}, {gravity[2]!r}]

[domain]
lower = [-0.05, -0.05, -0.02]
upper = [0.05, 0.05, 0.04]

[[materials]]
name = "glass"
density = 2500
youngs_modulus = 1e8
poisson = 0.3

[contact.default]
normal = "hertz_tsuji"
restitution = {restitution!r}
{law}

[[walls]]
material = "glass"
{wall}

[[particles]]
source = "file"
file = "ball.csv"

[output]
track = [0]
track_interval = {track_interval!r}
vtk_interval = 0
checkpoint_every_seconds = 0
"""


def plane(tilt):
    n = turn((0.0, 0.0, 1.0), tilt)
    return f"normal = [{n[0]!r}, {n[1]!r}, {n[2]!r}]\npoint = [0, 0, 0]"


def mesh(path, tilt=0.0):
    turned = f"\nrotation_axis = {list(TILT_AXIS)}\nrotation_degrees = {tilt!r}" if tilt else ""
    return f'shape = "mesh"\nfile = "{path}"\nunits = "m"' + turned


def run_tsubu(tsubu, folder, wall, x, v, w, **kw):
    """Runs the ball; returns track.csv's rows as (time, x, v, w, f), each vector a tuple."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "ball.csv"), "w") as f:
        f.write("id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz\n")
        f.write(",".join(repr(float(a)) for a in (0, 0, R, *x, *v, *w)) + "\n")
    path = os.path.join(folder, "scenario.toml")
    with open(path, "w") as f:
        f.write(scenario(wall, x, v, w, **kw))
    subprocess.run([tsubu, "run", path, "--out", os.path.join(folder, "out"), "--overwrite", "--threads", "1"],
                   check=True, stdout=subprocess.DEVNULL)
    rows = []
    with open(os.path.join(folder, "out", "track.csv")) as f:
        for r in csv.DictReader(f):
            vec = lambda a: tuple(float(r[a + c]) for c in "xyz")  # noqa: E731
            rows.append((float(r["time"]), (float(r["x"]), float(r["y"]), float(r["z"])), vec("v"), vec("w"), vec("f")))
    return rows


def distance(a, b):
    return math.sqrt(sum((p - q) ** 2 for p, q in zip(a, b)))


def impact(a, b, degrees):
    """The ball's start and velocity so that it first touches the plate at (a h, b h)."""
    angle = math.radians(degrees)
    v = (0.4 * math.sin(angle), 0.1 * math.sin(angle), -0.4 * math.cos(angle) - 0.05)
    fall = 1e-4
    hit = (a * H, b * H, R)
    x = tuple(hit[k] - fall / -v[2] * v[k] for k in range(3))
    return x, v


def rebounds(tsubu, tmp, plate_file):
    """Every impact point and angle with both integrators, the plate flat and tilted: the
    largest differences of position, velocity and spin between mesh and plane over the run
    (every 0.5 ms to 3 ms)."""
    out = []
    for tilt in (0.0, TILT_DEGREES):
        for integrator, dt in INTEGRATORS:
            for name, a, b in POINTS:
                for degrees in ANGLES:
                    x, v = impact(a, b, degrees)
                    x, v, w = turn(x, tilt), turn(v, tilt), turn(SPIN, tilt)
                    kw = dict(duration=3e-3, dt=dt, integrator=integrator, gravity=(0.0, 0.0, 0.0), restitution=0.5,
                              tangential="mindlin", track_interval=5e-4)
                    tag = f"{tilt:g}-{integrator}-{name.replace(' ', '')}-{degrees}"
                    on_mesh = run_tsubu(tsubu, os.path.join(tmp, "m-" + tag), mesh(plate_file, tilt), x, v, w, **kw)
                    on_plane = run_tsubu(tsubu, os.path.join(tmp, "p-" + tag), plane(tilt), x, v, w, **kw)
                    normal = turn((0.0, 0.0, 1.0), tilt)
                    assert len(on_mesh) == len(on_plane) and sum(a * b for a, b in zip(on_plane[-1][2], normal)) > 0, tag
                    dx = max(distance(m[1], p[1]) for m, p in zip(on_mesh, on_plane))
                    dv = max(distance(m[2], p[2]) for m, p in zip(on_mesh, on_plane))
                    dw = max(distance(m[3], p[3]) for m, p in zip(on_mesh, on_plane))
                    speed = math.sqrt(sum(c * c for c in on_plane[-1][2]))
                    spin = math.sqrt(sum(c * c for c in on_plane[-1][3]))
                    out.append((f"{integrator}, {'tilted' if tilt else 'flat'}", name, degrees, dx, dv, dw, speed, spin))
    return out


def rolling(tsubu, tmp, plate_file):
    """A ball rolling under gravity across the tilted plate's shared edges and vertices at
    0.3 m/s along a skew line for 0.1 s: its force on the mesh against the plane at every step."""
    x, v = turn((-0.03, -0.021, R - 2e-6), TILT_DEGREES), turn((0.3, 0.2, 0.0), TILT_DEGREES)
    kw = dict(duration=0.1, dt=1e-6, integrator="velocity_verlet", gravity=turn((0.0, 0.0, -9.81), TILT_DEGREES),
              restitution=0.5, tangential="mindlin", track_interval=0.0)
    big = plate_file.replace(".stl", "-big.stl")
    write_stl(big, plate_triangles(40, H))
    on_mesh = run_tsubu(tsubu, os.path.join(tmp, "roll-m"), mesh(big, TILT_DEGREES), x, v, (0, 0, 0), **kw)
    on_plane = run_tsubu(tsubu, os.path.join(tmp, "roll-p"), plane(TILT_DEGREES), x, v, (0, 0, 0), **kw)
    return [(p[0], distance(m[4], p[4]), math.sqrt(sum(c * c for c in p[4])), p[1]) for m, p in zip(on_mesh, on_plane)]


def grazing(tsubu, tmp):
    """Elastic and frictionless, the ball passes over a ridge or an apex, touching faces, edge
    and corner in turn: its kinetic energy after against before."""
    out = []
    for name, triangles, passes in [("ridge", ridge_triangles(), [(0.0003, 0.00015), (-0.004, 0.0002), (0.002, 0.00023)]),
                                    ("apex", apex_triangles(), [(0.0, 0.0002), (3e-5, 0.0002), (-1e-4, 0.00022),
                                                                (5e-5, 0.00015)])]:
        path = os.path.join(tmp, name + ".stl")
        write_stl(path, triangles)
        for y, height in passes:
            x, v = (-0.006, y, R + height), (0.5, 0.002, -0.02)
            kw = dict(duration=0.024, dt=1e-6, integrator="velocity_verlet", gravity=(0.0, 0.0, 0.0), restitution=1.0,
                      tangential="none", track_interval=0.0)
            rows = run_tsubu(tsubu, os.path.join(tmp, f"graze-{name}-{y}"), mesh(path), x, v, (0, 0, 0), **kw)
            touched = any(math.sqrt(sum(c * c for c in r[4])) > 0 for r in rows)
            before = 0.5 * sum(c * c for c in v)
            after = 0.5 * sum(c * c for c in rows[-1][2])
            out.append((name, y, height, touched, after / before - 1))
    return out


LIGGGHTS_INPUT = """atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
region box block -0.05 0.05 -0.05 0.05 -0.02 0.04 units box
create_box 1 box
neighbor 0.0005 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 1e8
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style gran model hertz tangential history
pair_coeff * *
${wall}
create_atoms 1 single ${x} ${y} ${z} units box
set atom 1 diameter 0.006 density 2500 vx ${vx} vy ${vy} vz ${vz} omegax 5 omegay -3 omegaz 2
fix integ all nve/sphere
timestep 1e-6
variable vx1 equal vx[1]
variable vy1 equal vy[1]
variable vz1 equal vz[1]
variable wx1 equal omegax[1]
variable wy1 equal omegay[1]
variable wz1 equal omegaz[1]
run 3000
print "FINAL ${vx1} ${vy1} ${vz1} ${wx1} ${wy1} ${wz1}"
"""


def run_liggghts(liggghts, folder, wall, x, v):
    """LIGGGHTS 3.8's ball (Hertz with its restitution damping, tangential history, e = 0.5,
    mu = 0.5, no gravity) for 3 ms: its final velocity and spin."""
    os.makedirs(folder, exist_ok=True)
    script = LIGGGHTS_INPUT.replace("${wall}", wall)
    for key, value in zip(("x", "y", "z", "vx", "vy", "vz"), (*x, *v)):
        script = script.replace("${%s}" % key, repr(value))
    path = os.path.join(folder, "in.ball")
    with open(path, "w") as f:
        f.write(script)
    done = subprocess.run([liggghts, "-in", path, "-log", os.path.join(folder, "log")], cwd=folder, check=True,
                          capture_output=True, text=True)
    line = next(s for s in done.stdout.splitlines() if s.startswith("FINAL"))
    numbers = [float(s) for s in line.split()[1:]]
    return tuple(numbers[:3]), tuple(numbers[3:])


def rebounds_liggghts(liggghts, tmp, plate_file):
    """LIGGGHTS on the same plate (fix mesh/surface) against its own plane (a primitive
    zplane): the differences of the final velocity and spin."""
    on_plane = "fix walls all wall/gran model hertz tangential history primitive type 1 zplane 0.0"
    on_mesh = (f"fix plate all mesh/surface file {plate_file} type 1\n"
               "fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes plate")
    out = []
    for name, a, b in POINTS:
        for degrees in ANGLES:
            x, v = impact(a, b, degrees)
            tag = f"{name.replace(' ', '')}-{degrees}"
            vm, wm = run_liggghts(liggghts, os.path.join(tmp, "lm-" + tag), on_mesh, x, v)
            vp, wp = run_liggghts(liggghts, os.path.join(tmp, "lp-" + tag), on_plane, x, v)
            out.append(("LIGGGHTS, flat", name, degrees, float("nan"), distance(vm, vp), distance(wm, wp),
                        math.sqrt(sum(c * c for c in vp)), math.sqrt(sum(c * c for c in wp))))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"))
    ap.add_argument("--liggghts", default=shutil.which("liggghts"), help="LIGGGHTS's executable (skipped when absent)")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "validation"))
    opts = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        plate_file = os.path.join(tmp, "plate.stl")
        write_stl(plate_file, plate_triangles(20, H))
        hits = rebounds(opts.tsubu, tmp, plate_file)
        roll = rolling(opts.tsubu, tmp, plate_file)
        graze = grazing(opts.tsubu, tmp)
        peer = rebounds_liggghts(opts.liggghts, tmp, plate_file) if opts.liggghts else []

    # One table: the rebounds (case "rebound", angle in degrees), the rolling ball (its largest
    # force difference) and the grazing passes (their offset across the ridge, m, and energy change).
    rows = [["rebound", code, name, degrees, dx, dv, dw, speed, spin, "", "", ""]
            for code, name, degrees, dx, dv, dw, speed, spin in hits + peer]
    worst = {}
    for code, name, degrees, dx, dv, dw, speed, spin in hits + peer:
        worst[code] = max(worst.get(code, 0.0), dv / speed, dw / spin)
        print(f"{code:24s} {name:12s} {degrees:3d} deg: |dx| {dx:.2e} m, |dv| {dv:.2e} m/s (of {speed:.3f}), "
              f"|dw| {dw:.2e} rad/s (of {spin:.1f})")
    for code, value in worst.items():
        print(f"{code}: largest difference from the plane, relative to the rebound's speed or spin: {value:.2e}")
    force_worst = max(r[1] for r in roll)
    force_largest = max(r[2] for r in roll)
    print(f"rolling: {len(roll)} steps over {distance(roll[0][3], roll[-1][3]) * 1e3:.1f} mm; largest force difference "
          f"{force_worst:.2e} N of {force_largest:.3e} N")
    rows.append(["rolling", "velocity_verlet, tilted", "", "", "", "", "", "", "", force_worst, force_largest, ""])
    for name, y, height, touched, gain in graze:
        print(f"grazing {name}, offset {y * 1e3:g} mm, {height * 1e6:g} um above: touched {touched}, "
              f"energy after / before - 1 = {gain:.2e}")
        rows.append(["grazing", "velocity_verlet", name, y, "", "", "", "", "", "", "", gain])
    header = ["case", "code", "feature", "angle_deg_or_offset_m", "dx_m", "dv_m_s", "dw_rad_s", "speed_m_s",
              "spin_rad_s", "force_difference_N", "largest_force_N", "energy_change"]

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.4))
    left, middle, right = axes
    markers = {"face": "o", "edge": "s", "diagonal": "D", "vertex of 8": "*", "vertex of 4": "^"}
    floor = 1e-17  # where an exact zero is drawn
    codes = [("velocity_verlet, tilted", "C0", 0), ("block_hermite, tilted", "C1", 1), ("LIGGGHTS, flat", "C3", 2)]
    for code, colour, shift in codes:
        for name in markers:
            pts = [(d + shift - 1, max(dv / s, dw / w, floor)) for c, n, d, _, dv, dw, s, w in hits + peer
                   if c == code and n == name]
            if pts:
                left.semilogy([p[0] for p in pts], [p[1] for p in pts], markers[name], color=colour, ms=6, mfc="none",
                              label=code.replace("_", " ") if name == "face" else None)
    for name, marker in markers.items():
        left.plot([], [], marker, color="0.4", mfc="none", label=name)
    left.set_xlabel("impact angle from the normal (degrees)")
    left.set_ylabel("mesh against plane: max(|Δv|/|v|, |Δω|/|ω|)")
    left.set_title("(a) rebounds off 800 triangles (flat: the same bits)", fontsize=10)
    left.legend(fontsize=7, loc="center right", ncol=2)
    t = [r[0] * 1e3 for r in roll]
    middle.semilogy(t, [max(r[1] / force_largest, floor) for r in roll], lw=0.6)
    middle.set_xlabel("time (ms)")
    middle.set_ylabel("|F_mesh − F_plane| / largest |F|")
    middle.set_title(f"(b) rolling {distance(roll[0][3], roll[-1][3]) * 1e3:.0f} mm over edges, tilted", fontsize=10)
    middle.set_ylim(floor / 2, 1e-8)
    labels = [f"{n} {y * 1e3:g} mm" for n, y, _, _, _ in graze]
    right.bar(range(len(graze)), [g for *_, g in graze], color="C2")
    right.axhline(0, color="k", lw=0.5)
    right.set_xticks(range(len(graze)))
    right.set_xticklabels(labels, rotation=35, ha="right", fontsize=7)
    right.set_ylabel("kinetic energy after / before − 1")
    right.set_title("(c) elastic grazing over a ridge or an apex", fontsize=10)
    save(fig, opts.out, "mesh-walls", header, rows)


if __name__ == "__main__":
    main()
