#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# Copyright (c) 2026, the tsubu developers
"""How many steps per contact the tangential spring needs: rebound spin and velocities of an
oblique collision against a reference run.

    python3 tools/oblique_impact.py [--tsubu build/tsubu] [--csv results.csv] [options]

Two set-ups, no gravity, glass spheres of d = 2 mm (E = 1e8 Pa, density 2500 kg/m^3):
a sphere hitting a wall (`wall`), and two equal spheres meeting in their centre-of-mass
frame (`pair`: both spin). The relative normal speed at impact is u_n (0.5 m/s), the
relative tangential speed ratio x u_n. Each case (set-up, normal law, tangential law, ratio)
is run

  - once as the reference: velocity Verlet at --ref-steps (4000) steps per contact; its
    series.csv, written every step, gives the contact time t_c;
  - with velocity Verlet at dt = t_c / N, N = 10, 20, 40, 80;
  - with block-step Hermite at kappa_c = 0.01, 0.02, 0.04 (the default), 0.08.

and the rebound state of sphere 0 (track.csv at the end of the run) is compared with the
reference's: spin w_y (relative error), tangential and normal rebound velocity (relative
to the reference's). `evals` is run.json's particle_force_evaluations per particle, over the
whole run (a short approach of 0.173 t_c and the flight after the contact included), for
both integrators. Printed: one line per case, then the worst error of each integrator
setting over all cases, with the case. The scenarios are written to a temporary folder;
nothing is kept unless --keep is given.

Normal laws: hertz_sediment (alpha, default 0.2), hertz_tsuji (restitution), linear
(stiffness, restitution); tangential: mindlin, linear_coulomb (stiffness_ratio: the
normal law's default 2(1-nu)/(2-nu) unless --stiffness-ratio).
"""
import argparse
import csv
import json
import math
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent

DIAMETER = 0.002  # m
DENSITY = 2500.0  # kg/m^3
YOUNG = 1e8  # Pa
LINEAR_STIFFNESS = 1000.0  # N/m: max overlap 2.5 % of d at 0.5 m/s on a wall
APPROACH = 0.173  # the gap at the start, as a share of t_c flown at u_n (not a multiple of any step)
AFTER = 0.8  # flight after the contact, as a share of t_c (estimated) past the estimated end

VV_STEPS = [10, 20, 40, 80]
KAPPAS = [0.01, 0.02, 0.04, 0.08]
RATIOS = [0.02, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 3.0]


def estimated_contact_time(args, geometry, normal):
    """An elastic estimate of t_c, only to choose the reference's step and the run's length."""
    m = DENSITY * math.pi * DIAMETER**3 / 6
    m_eff = m if geometry == "wall" else m / 2
    if normal == "linear":
        return math.pi * math.sqrt(m_eff / args.stiffness)
    r_eff = DIAMETER / 2 if geometry == "wall" else DIAMETER / 4
    e_eff = YOUNG / (2 * (1 - args.poisson**2))
    k = 4 / 3 * e_eff * math.sqrt(r_eff)
    return 2.94 * (m_eff**2 / (k**2 * args.speed)) ** 0.2


def contact_table(args, normal, tangential):
    lines = [f'normal = "{normal}"', f'tangential = "{tangential}"', f"friction = {args.friction}"]
    if normal == "hertz_sediment":
        lines.append(f"alpha = {args.alpha}")
    else:
        lines.append(f"restitution = {args.restitution}")
    if normal == "linear":
        lines.append(f"stiffness = {args.stiffness}")
    if tangential == "linear_coulomb" and args.stiffness_ratio:
        lines.append(f"stiffness_ratio = {args.stiffness_ratio}")
    if tangential == "mindlin" and args.friction_bound:
        lines.append(f'friction_bound = "{args.friction_bound}"')
    return "\n".join(lines)


def particles_csv(args, geometry, ratio, gap):
    """Sphere 0 (and 1) just apart, approaching at u_n along z, sliding at ratio u_n along x."""
    r = DIAMETER / 2
    u_n, u_t = args.speed, ratio * args.speed
    rows = ["x,y,z,d,vx,vy,vz"]
    if geometry == "wall":
        rows.append(f"0,0,{r + gap!r},{DIAMETER},{u_t!r},0,{-u_n!r}")
    else:  # centre-of-mass frame: each sphere moves at half the relative velocity
        rows.append(f"0,0,{r + gap / 2!r},{DIAMETER},{u_t / 2!r},0,{-u_n / 2!r}")
        rows.append(f"0,0,{-(r + gap / 2)!r},{DIAMETER},{-u_t / 2!r},0,{u_n / 2!r}")
    return "\n".join(rows) + "\n"


def scenario(args, case, integrator, dt, duration, series_every_step=False, kappa_c=None):
    geometry, normal, tangential, _ = case
    wall = ""
    if geometry == "wall":
        wall = '[[walls]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = "glass"\n'
    track = "[0]" if geometry == "wall" else "[0, 1]"
    block = f"\n[simulation.block_steps]\nkappa_c = {kappa_c}\n" if kappa_c is not None else ""
    return f"""[simulation]
duration = {duration!r}
dt = {dt!r}
integrator = "{integrator}"
gravity = [0, 0, 0]
{block}
[domain]
lower = [-0.02, -0.02, -0.02]
upper = [0.02, 0.02, 0.02]

[[materials]]
name = "glass"
density = {DENSITY}
youngs_modulus = {YOUNG}
poisson = {args.poisson}

[contact.default]
{contact_table(args, normal, tangential)}

{wall}
[[particles]]
source = "csv"
material = "glass"
file = "grains.csv"

[output]
series_interval = {0 if series_every_step else 1e300}
vtk_interval = 0
contacts = false
track = {track}
track_interval = 1e300
checkpoint_every_steps = 0
checkpoint_every_seconds = 0
"""


def run(args, folder, text):
    """Runs one scenario: (state of sphere 0 at the end, run.json, out folder), or None when
    tsubu stops it with a numerical failure (exit code 3; its message is kept in args.failures)."""
    path = folder / "scenario.toml"
    path.write_text(text)
    out = folder / "out"
    result = subprocess.run([args.tsubu, "run", str(path), "--out", str(out), "--overwrite"],
                            capture_output=True, text=True)
    if result.returncode == 3:
        args.failures.append(text + "\n# " + (result.stderr or result.stdout).strip())
        return None
    if result.returncode != 0:
        sys.exit(f"{args.tsubu} run {path} failed ({result.returncode}):\n{result.stderr}{result.stdout}")
    with open(out / "track.csv") as f:
        rows = [row for row in csv.DictReader(f) if row["id"] == "0"]
    last = {key: float(value) for key, value in rows[-1].items()}
    if last["contacts"] != 0:
        sys.exit(f"{path}: sphere 0 is still in contact at the end of the run")
    return last, json.loads((out / "run.json").read_text()), out


def contact_time(series_path, dt):
    """Steps with a contact in a series.csv written every step, times dt."""
    with open(series_path) as f:
        return sum(1 for row in csv.DictReader(f) if float(row["contacts"]) > 0) * dt


def compare(outcome, ref, n_particles):
    """(spin, tangential, normal) relative errors of the rebound against the reference and the
    evaluations per particle; None for a run that failed."""
    if outcome is None:
        return None
    state, info, _ = outcome
    def rel(key):
        return abs(state[key] - ref[key]) / abs(ref[key]) if ref[key] != 0 else math.inf
    return rel("wy"), rel("vx"), rel("vz"), info["particle_force_evaluations"] / n_particles


def measure(args, case, folder):
    geometry, normal, tangential, ratio = case
    n_particles = 1 if geometry == "wall" else 2
    t_est = estimated_contact_time(args, geometry, normal)
    gap = APPROACH * t_est * args.speed
    duration = (APPROACH + 1 + AFTER) * t_est
    (folder / "grains.csv").write_text(particles_csv(args, geometry, ratio, gap))

    dt_ref = t_est / args.ref_steps
    outcome = run(args, folder, scenario(args, case, "velocity_verlet", dt_ref, duration, True))
    if outcome is None:
        sys.exit(f"the reference run of {case} failed:\n{args.failures[-1]}")
    ref, _, out = outcome
    t_c = contact_time(out / "series.csv", dt_ref)
    results = {"t_c": t_c, "wy": ref["wy"], "vx": ref["vx"], "vz": ref["vz"]}
    for n in args.vv_steps:
        outcome = run(args, folder, scenario(args, case, "velocity_verlet", t_c / n, duration))
        results[f"vv{n}"] = compare(outcome, ref, n_particles)
    for kappa in args.kappas:
        text = scenario(args, case, "block_hermite", duration / args.bh_dt, duration, kappa_c=kappa)
        results[f"bh{kappa}"] = compare(run(args, folder, text), ref, n_particles)
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tsubu", default=str(ROOT / "build" / "tsubu"))
    parser.add_argument("--geometries", default="wall,pair")
    parser.add_argument("--normals", default="hertz_sediment,hertz_tsuji,linear")
    parser.add_argument("--tangentials", default="mindlin,linear_coulomb")
    parser.add_argument("--ratios", default=",".join(map(str, RATIOS)),
                        help="tangential / normal relative speed at impact")
    parser.add_argument("--speed", type=float, default=0.5, help="u_n, m/s (relative normal speed)")
    parser.add_argument("--friction", type=float, default=0.3)
    parser.add_argument("--poisson", type=float, default=0.3)
    parser.add_argument("--alpha", type=float, default=0.2, help="hertz_sediment's dashpot")
    parser.add_argument("--restitution", type=float, default=0.8, help="hertz_tsuji and linear")
    parser.add_argument("--stiffness", type=float, default=LINEAR_STIFFNESS, help="linear's k_n, N/m")
    parser.add_argument("--stiffness-ratio", type=float, default=0, help="linear_coulomb's k_t/k_n (0: default)")
    parser.add_argument("--friction-bound", choices=["spring", "total"], default=None, help="mindlin only")
    parser.add_argument("--ref-steps", type=int, default=4000, help="reference steps per (estimated) contact")
    parser.add_argument("--vv-steps", default=",".join(map(str, VV_STEPS)), help="velocity Verlet steps per t_c")
    parser.add_argument("--kappas", default=",".join(map(str, KAPPAS)), help="block steps' kappa_c")
    parser.add_argument("--bh-dt", type=int, default=4, help="block steps: dt (the longest step) is the run / this")
    parser.add_argument("--csv", help="write every result to this file")
    parser.add_argument("--failures", help="write the scenarios of failed runs (with the message) to this file")
    parser.add_argument("--keep", help="keep the scenarios and outputs of the last case in this folder")
    args = parser.parse_args()
    args.vv_steps = [int(n) for n in args.vv_steps.split(",") if n]
    args.kappas = [float(k) for k in args.kappas.split(",") if k]
    args.failures_file, args.failures = args.failures, []

    cases = [(g, n, t, float(r)) for g in args.geometries.split(",") for n in args.normals.split(",")
             for t in args.tangentials.split(",") for r in args.ratios.split(",")]
    methods = [f"vv{n}" for n in args.vv_steps] + [f"bh{k}" for k in args.kappas]
    labels = {f"vv{n}": f"VV {n}/t_c" for n in args.vv_steps} | {f"bh{k}": f"BH kappa_c {k}" for k in args.kappas}
    print(f"friction {args.friction}, poisson {args.poisson}, u_n {args.speed} m/s; spin error % per method "
          f"({', '.join(labels[m] for m in methods)}); FAIL: stopped with a numerical failure")
    start = time.monotonic()
    table = []
    with tempfile.TemporaryDirectory(prefix="oblique_") as tmp:
        for case in cases:
            res = measure(args, case, pathlib.Path(tmp))
            table.append((case, res))
            print(f"{case[0]:4} {case[1]:14} {case[2]:14} {case[3]:5}  t_c {res['t_c']:.3e} s  "
                  f"w_ref R/u_t {res['wy'] * DIAMETER / 2 / (case[3] * args.speed):+.3f}  spin err %: "
                  + " ".join("   FAIL" if res[m] is None else f"{100 * res[m][0]:7.3f}" for m in methods),
                  flush=True)
        if args.keep:
            shutil.copytree(tmp, args.keep, dirs_exist_ok=True)

    print(f"\nworst over {len(cases)} cases ({time.monotonic() - start:.0f} s):")
    print("| method | spin | tangential v | normal v | evaluations per particle | worst spin case | failed runs |")
    print("|---|---|---|---|---|---|---|")
    for m in methods:
        done = [(case, res[m]) for case, res in table if res[m] is not None]
        if not done:
            print(f"| {labels[m]} | – | – | – | – | – | {len(table)} |")
            continue
        case, worst = max(done, key=lambda cr: cr[1][0])
        evals = [r[3] for _, r in done]
        print(f"| {labels[m]} | {100 * worst[0]:.2f} % | {100 * max(r[1] for _, r in done):.2f} % | "
              f"{100 * max(r[2] for _, r in done):.2f} % | {min(evals):.0f}-{max(evals):.0f} | "
              f"{case[0]} {case[1]} {case[2]} ratio {case[3]} | {len(table) - len(done)} |")

    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["geometry", "normal", "tangential", "ratio", "friction", "poisson", "t_c", "wy_ref",
                        "vx_ref", "vz_ref", "method", "spin_err", "vt_err", "vn_err", "evals_per_particle"])
            for case, res in table:
                for m in methods:
                    w.writerow(list(case) + [args.friction, args.poisson, res["t_c"], res["wy"], res["vx"],
                                             res["vz"], labels[m]] + list(res[m] or ["fail"] * 4))
    if args.failures_file and args.failures:
        pathlib.Path(args.failures_file).write_text("\n\n".join(args.failures) + "\n")
    if args.failures:
        print(f"{len(args.failures)} runs stopped with a numerical failure"
              + (f" (scenarios in {args.failures_file})" if args.failures_file else " (--failures FILE keeps them)"))


if __name__ == "__main__":
    main()
