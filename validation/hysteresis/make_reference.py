#!/usr/bin/env python3
"""Runs LIGGGHTS (`liggghts`, Debian's LIGGGHTS 3.8) on the model HH cases of cases.csv and
writes one reference file per case, reference/<name>.csv, with one row per step:

  step, overlap, overlap2, fn, x, y, z, vx, vy, vz, fx, fy, fz, wx, wy, wz

x, v, f, w are the position, velocity, force and angular velocity of sphere 1 after the
step; overlap is its contact's overlap (pair: 2R - |x1 - x2|, wall and piston: with the floor
z = 0) and fn the normal force on it (pair and driven: along (x1 - x2)/|x1 - x2|; wall: fz);
for the piston, overlap2 is the overlap with the plate and fn the total fz. Numbers are
written with 17 significant digits.

Usage: make_reference.py [--liggghts PATH] [--keep DIR] [case ...]
Python 3 standard library only.
"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
COLUMNS = ["step", "overlap", "overlap2", "fn", "x", "y", "z", "vx", "vy", "vz",
           "fx", "fy", "fz", "wx", "wy", "wz"]


def read_cases(path):
    with open(path) as f:
        rows = [line for line in f if line.strip() and not line.startswith("#")]
    return list(csv.DictReader(rows))


def segments(motion):
    """'n1:v1 n2:v2' -> [(n1, v1), (n2, v2)]."""
    out = []
    for part in motion.split():
        n, v = part.split(":")
        out.append((int(n), float(v)))
    return out


def velocity_variable(motion):
    """A LIGGGHTS equal-style formula giving the velocity of each step from `motion`."""
    terms, start = [], 0
    for n, v in segments(motion):
        terms.append("(%r)*(step>%d)*(step<=%d)" % (v, start, n))
        start = n
    return "+".join(terms) if terms else "0"


def plate_stl(path, z):
    """A 20 mm square at height z, two triangles (the sphere stays away from the diagonal)."""
    a = 0.01
    tri = [((-a, -a, z), (a, -a, z), (a, a, z)), ((-a, -a, z), (a, a, z), (-a, a, z))]
    with open(path, "w") as f:
        f.write("solid plate\n")
        for t in tri:
            f.write("  facet normal 0 0 1\n    outer loop\n")
            for p in t:
                f.write("      vertex %r %r %r\n" % p)
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid plate\n")


def liggghts_input(c, dump):
    g = c["geometry"]
    r = 0.5 * float(c["diameter"])
    gap = float(c["gap"])
    vn, vt = float(c["vn"]), float(c["vt"])
    pair2 = lambda key: "peratomtypepair 2 %s %s %s %s" % ((c[key],) * 4)
    damping = "on" if c["tangential_damping"] == "1" else "off"
    model = "model hooke/hysteresis tangential history"
    settings = "tangential_damping %s" % damping  # pair_style: after the models; wall/gran: at the end
    lines = [
        "atom_style granular",
        "atom_modify map array sort 0 0.0",
        "boundary f f f",
        "newton off",
        "communicate single vel yes",
        "units si",
        "region box block -0.01 0.01 -0.01 0.01 -0.01 0.01 units box",
        "create_box 2 box",
        "neighbor 0.0005 bin",
        "neigh_modify delay 0",
        "fix m1 all property/global youngsModulus peratomtype %s %s" % (c["youngs_modulus"], c["youngs_modulus"]),
        "fix m2 all property/global poissonsRatio peratomtype %s %s" % (c["poisson"], c["poisson"]),
        "fix m3 all property/global coefficientRestitution " + pair2("restitution"),
        "fix m4 all property/global coefficientFriction " + pair2("friction"),
        "fix m5 all property/global characteristicVelocity scalar %s" % c["characteristic_velocity"],
        "fix m6 all property/global coefficientMaxElasticStiffness " + pair2("max_stiffness_ratio"),
        "fix m7 all property/global coefficientAdhesionStiffness " + pair2("adhesion_stiffness_ratio"),
        "fix m8 all property/global coefficientPlasticityDepth " + pair2("plasticity_depth"),
        "pair_style gran %s %s" % (model, settings),
        "pair_coeff * *",
        "timestep %s" % c["dt"],
    ]
    atoms = []
    if g == "pair":
        atoms = [((-(r + gap / 2), 0, 0), (vn / 2, vt / 2, 0)), ((r + gap / 2, 0, 0), (-vn / 2, -vt / 2, 0))]
    elif g == "wall":
        atoms = [((0, 0, r + gap), (vt, 0, -vn))]
    elif g == "driven":
        atoms = [((-(2 * r + gap), 0, 0), (0, 0, 0)), ((0, 0, 0), (0, 0, 0))]
    elif g == "piston":
        atoms = [((0.002, -0.003, r + gap / 2), (0, 0, 0))]
    else:
        raise SystemExit("unknown geometry " + g)
    for k, (x, v) in enumerate(atoms, start=1):
        lines.append("create_atoms 1 single %r %r %r units box" % x)
        lines.append("set atom %d diameter %s density %s vx %r vy %r vz %r"
                     % (k, c["diameter"], c["density"], v[0], v[1], v[2]))
    if g == "driven":
        lines += ["group one id 1", "group two id 2",
                  "variable vdrive equal \"%s\"" % velocity_variable(c["motion"]),
                  "fix drive one move variable NULL NULL NULL v_vdrive NULL NULL",
                  "fix hold two move linear 0 0 0"]
    else:
        lines.append("fix integr all nve/sphere")
    if g in ("wall", "piston"):
        lines.append("fix floor all wall/gran %s primitive type 2 zplane 0.0 %s" % (model, settings))
    if g == "piston":
        plate_stl(os.path.join(os.path.dirname(dump), "plate.stl"), 2 * r + gap)
        lines += ["fix plate all mesh/surface file plate.stl type 2",
                  "fix piston all wall/gran %s mesh n_meshes 1 meshes plate %s" % (model, settings),
                  "variable zero equal 0",
                  "variable vplate equal \"%s\"" % velocity_variable(c["motion"]),
                  "fix push all move/mesh mesh plate linear/variable v_zero v_zero v_vplate"]
    lines += ["dump d all custom 1 %s id x y z vx vy vz fx fy fz omegax omegay omegaz" % os.path.basename(dump),
              "dump_modify d sort id format \"%d" + " %.17g" * 12 + "\"",
              "run %s" % c["steps"]]
    return "\n".join(lines) + "\n"


def read_dump(path):
    """{step: {id: [x y z vx vy vz fx fy fz wx wy wz]}}"""
    frames, step, lines = {}, None, open(path).read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            frames[step] = {}
            i += 2
        elif lines[i].startswith("ITEM: ATOMS"):
            i += 1
            while i < len(lines) and lines[i].strip() and not lines[i].startswith("ITEM"):
                v = lines[i].split()
                frames[step][int(v[0])] = [float(t) for t in v[1:]]
                i += 1
        else:
            i += 1
    return frames


def reference_rows(c, frames):
    g = c["geometry"]
    r = 0.5 * float(c["diameter"])
    dt = float(c["dt"])
    plate = 2 * r + float(c["gap"])
    plate_v = dict()
    if g == "piston":
        start = 0
        for n, v in segments(c["motion"]):
            for s in range(start + 1, n + 1):
                plate_v[s] = v
            start = n
    rows = []
    for step in sorted(frames):
        if step > 0:
            plate += plate_v.get(step, 0.0) * dt  # the mesh moves by v dt each step
        a = frames[step][1]
        overlap2 = 0.0
        if g in ("pair", "driven"):
            b = frames[step][2]
            d = [a[k] - b[k] for k in range(3)]
            dist = math.sqrt(sum(t * t for t in d))
            overlap = 2 * r - dist
            fn = sum(a[6 + k] * d[k] / dist for k in range(3))
        else:
            overlap = r - a[2]
            fn = a[8]
            if g == "piston":
                overlap2 = r - (plate - a[2])
        rows.append([step, overlap, overlap2, fn] + a)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--liggghts", default=shutil.which("liggghts") or "/usr/bin/liggghts")
    ap.add_argument("--keep", help="keep the LIGGGHTS inputs and dumps in this folder")
    ap.add_argument("cases", nargs="*")
    args = ap.parse_args()
    out_dir = os.path.join(HERE, "reference")
    os.makedirs(out_dir, exist_ok=True)
    for c in read_cases(os.path.join(HERE, "cases.csv")):
        if args.cases and c["name"] not in args.cases:
            continue
        work = os.path.join(args.keep, c["name"]) if args.keep else tempfile.mkdtemp()
        os.makedirs(work, exist_ok=True)
        dump = os.path.join(work, "out.dump")
        with open(os.path.join(work, "in.case"), "w") as f:
            f.write(liggghts_input(c, dump))
        run = subprocess.run([args.liggghts, "-in", "in.case", "-log", "log.liggghts"], cwd=work,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             errors="replace")
        if run.returncode != 0 or "ERROR" in run.stdout:
            sys.stderr.write(run.stdout[-3000:])
            raise SystemExit("LIGGGHTS failed on case %s (inputs in %s)" % (c["name"], work))
        rows = reference_rows(c, read_dump(dump))
        with open(os.path.join(out_dir, c["name"] + ".csv"), "w") as f:
            f.write("# LIGGGHTS 3.8 (%s), case %s of cases.csv; written by make_reference.py\n"
                    % (args.liggghts, c["name"]))
            f.write(",".join(COLUMNS) + "\n")
            for row in rows:
                f.write("%d," % row[0] + ",".join("%.17g" % v for v in row[1:]) + "\n")
        touching = sum(1 for row in rows if row[1] > 0 or row[2] > 0)
        print("%-22s %5d steps, %5d in contact, max overlap %.4g m" % (c["name"], len(rows) - 1, touching,
                                                                         max(max(row[1], row[2]) for row in rows)))
        if not args.keep:
            shutil.rmtree(work)


if __name__ == "__main__":
    main()
