#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# Copyright (c) 2026, the tsubu developers
"""How many steps per contact a frictional collision needs: the rebound spin and velocities of
an oblique impact, with velocity Verlet and block steps, against a fine reference run.

    python3 tools/oblique_impact.py [--tsubu build/tsubu] [--csv FILE] [options]

Two set-ups, no gravity, glass spheres of d = 2 mm (2500 kg/m^3, --young 1e8 Pa, --poisson 0.3):
a sphere hitting a wall of the same glass (`wall`), and two equal spheres meeting in their
centre-of-mass frame (`pair`: both spin). The relative normal speed at impact is u_n
(0.5 m/s), the relative tangential speed ratio * u_n, from nearly head on (0.02) to grazing
(3). Each case (set-up, normal law, tangential law, ratio, approach) is run

  - as the reference: velocity Verlet at --ref-steps (4000) steps per estimated contact
    time; its series.csv, written every step, gives the contact time t_c;
  - with velocity Verlet at dt = t_c / N, N = 10, 20, 40, 80 (--vv-steps);
  - with block steps (block_hermite) at kappa_c = 0.01, 0.02, 0.04 (the default), 0.08
    (--kappas), dt (the longest step) a quarter of the run (--bh-dt);

and the rebound of sphere 0 (its row of track.csv at the end of the run) is compared with
the reference's: the spin w_y and the rebound velocity along the wall (x) and normal to it
(z; in a pair, along the line of centres at the start), each relative to the reference's.
As relative errors mean little where the reference spin is nearly zero (an elastic sticking
impact can give the spin back), the spin's error is also given in units of
w_s = u_t / (n R), each sphere's share of the incoming slip as spin (n = 1 on a wall, 2 in
a pair). `approach` is the gap at the start as the share of the estimated contact time
flown at u_n: it sets where the touch falls between two steps, and the result of a coarse
step depends on it, so each case runs at three (--approaches).

Evaluations are run.json's particle_force_evaluations per particle, over the whole run:
for velocity Verlet the steps of the run (the approach and the flight after the contact
included, about 2 N); for block steps those of every level, the short steps of the event
rule at touch and release included (about 30 a contact).

Printed: one line per case (spin errors in %), then a table of the worst and the median
error of each integrator setting over all cases, with the worst case. A run that tsubu stops
with a numerical failure (exit code 3) is counted as failed; --failures FILE keeps its
scenario. The scenarios go to a temporary folder (kept with --keep DIR: the last case's).

Laws: normal hertz_sediment (--alpha, 0.2 as tsubu's default), hertz_tsuji and linear
(--restitution 0.8; linear's --stiffness 1000 N/m); tangential mindlin and linear_coulomb
(--stiffness-ratio, default the law's 2(1-nu)/(2-nu)); --friction 0.3. The default run (324
cases, 2916 short tsubu runs, one at a time) takes 1-2 minutes. The worst cases found so far
add, for example, --friction 1 --poisson 0, or --restitution 0.95, or --alpha 0.05, and
finer --vv-steps and --kappas.
"""
import argparse
import csv
import json
import math
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent

DIAMETER = 0.002  # m
DENSITY = 2500.0  # kg/m^3
AFTER = 0.8  # flight after the contact: the run lasts (approach + 1 + AFTER) estimated contact times

VV_STEPS = "10,20,40,80"
KAPPAS = "0.01,0.02,0.04,0.08"
RATIOS = "0.02,0.1,0.2,0.3,0.5,0.7,1,1.5,3"
APPROACHES = "0.173,0.231,0.287"


def estimated_contact_time(args, geometry, normal):
    """An elastic estimate of t_c, only to choose the reference's step and the run's length."""
    m = DENSITY * math.pi * DIAMETER**3 / 6
    m_eff = m if geometry == "wall" else m / 2
    if normal == "linear":
        return math.pi * math.sqrt(m_eff / args.stiffness)
    r_eff = DIAMETER / 2 if geometry == "wall" else DIAMETER / 4
    e_eff = args.young / (2 * (1 - args.poisson**2))
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
    """Sphere 0 (and 1) `gap` apart, closing at u_n along z and sliding at ratio u_n along x."""
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
    geometry, normal, tangential = case[:3]
    wall = ""
    if geometry == "wall":
        wall = '[[walls]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = "glass"\n'
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
youngs_modulus = {args.young}
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
track = [0]
track_interval = 1e300
checkpoint_every_steps = 0
checkpoint_every_seconds = 0
"""


def run(args, folder, text):
    """Runs one scenario: (sphere 0's last row of track.csv, run.json, out folder), or None when
    tsubu stops it with a numerical failure (exit code 3; the scenario is kept in args.failed)."""
    path = folder / "scenario.toml"
    path.write_text(text)
    out = folder / "out"
    result = subprocess.run([args.tsubu, "run", str(path), "--out", str(out), "--overwrite"],
                            capture_output=True, text=True)
    if result.returncode == 3:
        args.failed.append(text + "# grains.csv:\n# " + (folder / "grains.csv").read_text().replace("\n", "\n# ")
                           + (result.stderr or result.stdout).strip())
        return None
    if result.returncode != 0:
        sys.exit(f"{args.tsubu} run {path} failed ({result.returncode}):\n{result.stderr}{result.stdout}")
    with open(out / "track.csv") as f:
        last = {key: float(value) for key, value in list(csv.DictReader(f))[-1].items()}
    if last["contacts"] != 0:
        sys.exit(f"{path}: sphere 0 is still in contact at the end of the run")
    return last, json.loads((out / "run.json").read_text()), out


def contact_time(series_path, dt):
    """Steps with a contact in a series.csv written every step, times dt."""
    with open(series_path) as f:
        return sum(1 for row in csv.DictReader(f) if float(row["contacts"]) > 0) * dt


def compare(outcome, ref, n_particles, w_s):
    """Errors of a run against the reference: {spin, spin/w_s, vt, vn, evals}, or None if it failed."""
    if outcome is None:
        return None
    state, info, _ = outcome

    def rel(key):
        return abs(state[key] - ref[key]) / abs(ref[key]) if ref[key] != 0 else math.inf

    return {"spin": rel("wy"), "spin_ws": abs(state["wy"] - ref["wy"]) / w_s if w_s else math.nan,
            "vt": rel("vx"), "vn": rel("vz"), "evals": info["particle_force_evaluations"] / n_particles}


def measure(args, case, folder):
    geometry, normal, tangential, ratio, approach = case
    n_particles = 1 if geometry == "wall" else 2
    t_est = estimated_contact_time(args, geometry, normal)
    duration = (approach + 1 + AFTER) * t_est
    (folder / "grains.csv").write_text(particles_csv(args, geometry, ratio, approach * t_est * args.speed))

    dt_ref = t_est / args.ref_steps
    outcome = run(args, folder, scenario(args, case, "velocity_verlet", dt_ref, duration, series_every_step=True))
    if outcome is None:
        sys.exit(f"the reference run of {case} failed:\n{args.failed[-1]}")
    ref, _, out = outcome
    t_c = contact_time(out / "series.csv", dt_ref)
    w_s = ratio * args.speed / (n_particles * DIAMETER / 2)
    result = {"t_c": t_c, "wy": ref["wy"], "vx": ref["vx"], "vz": ref["vz"], "w_s": w_s}
    for n in args.vv_steps:
        outcome = run(args, folder, scenario(args, case, "velocity_verlet", t_c / n, duration))
        result[f"vv{n}"] = compare(outcome, ref, n_particles, w_s)
    for kappa in args.kappas:
        text = scenario(args, case, "block_hermite", duration / args.bh_dt, duration, kappa_c=kappa)
        result[f"bh{kappa}"] = compare(run(args, folder, text), ref, n_particles, w_s)
    return result


def numbers(text, kind):
    return [kind(x) for x in text.split(",") if x]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tsubu", default=str(ROOT / "build" / "tsubu"))
    parser.add_argument("--geometries", default="wall,pair")
    parser.add_argument("--normals", default="hertz_sediment,hertz_tsuji,linear")
    parser.add_argument("--tangentials", default="mindlin,linear_coulomb")
    parser.add_argument("--ratios", default=RATIOS, help="tangential / normal relative speed at impact")
    parser.add_argument("--approaches", default=APPROACHES,
                        help="gap at the start, as the share of the estimated t_c flown at u_n to close it")
    parser.add_argument("--speed", type=float, default=0.5, help="u_n, m/s (relative normal speed)")
    parser.add_argument("--friction", type=float, default=0.3)
    parser.add_argument("--poisson", type=float, default=0.3)
    parser.add_argument("--young", type=float, default=1e8, help="Young's modulus of spheres and wall, Pa")
    parser.add_argument("--alpha", type=float, default=0.2, help="hertz_sediment's dashpot")
    parser.add_argument("--restitution", type=float, default=0.8, help="hertz_tsuji and linear")
    parser.add_argument("--stiffness", type=float, default=1000.0, help="linear's k_n, N/m")
    parser.add_argument("--stiffness-ratio", type=float, default=0, help="linear_coulomb's k_t/k_n (0: the default)")
    parser.add_argument("--friction-bound", choices=["spring", "total"], default=None, help="mindlin's")
    parser.add_argument("--ref-steps", type=int, default=4000, help="reference steps per estimated contact time")
    parser.add_argument("--vv-steps", default=VV_STEPS, help="velocity Verlet steps per contact")
    parser.add_argument("--kappas", default=KAPPAS, help="block steps' kappa_c")
    parser.add_argument("--bh-dt", type=int, default=4, help="block steps: dt (the longest step) is the run / this")
    parser.add_argument("--csv", help="write every result to this file")
    parser.add_argument("--failures", help="write the scenarios of the failed runs to this file")
    parser.add_argument("--keep", help="copy the last case's scenarios and outputs to this folder")
    args = parser.parse_args()
    args.vv_steps, args.kappas = numbers(args.vv_steps, int), numbers(args.kappas, float)
    args.failed = []

    cases = [(g, n, t, r, a) for g in args.geometries.split(",") for n in args.normals.split(",")
             for t in args.tangentials.split(",") for r in numbers(args.ratios, float)
             for a in numbers(args.approaches, float)]
    methods = [f"vv{n}" for n in args.vv_steps] + [f"bh{k}" for k in args.kappas]
    labels = {f"vv{n}": f"VV {n}/t_c" for n in args.vv_steps} | {f"bh{k}": f"BH kappa_c {k}" for k in args.kappas}
    print(f"friction {args.friction}, poisson {args.poisson}, E {args.young:g} Pa, u_n {args.speed} m/s; spin "
          f"error in % of the reference's for {', '.join(labels[m] for m in methods)} (FAIL: numerical failure)")
    start = time.monotonic()
    table = []
    with tempfile.TemporaryDirectory(prefix="oblique_") as tmp:
        for case in cases:
            res = measure(args, case, pathlib.Path(tmp))
            table.append((case, res))
            w_ratio = res["wy"] / res["w_s"] if res["w_s"] else math.nan
            print(f"{case[0]:4} {case[1]:14} {case[2]:14} ratio {case[3]:<5g} approach {case[4]:<5g} "
                  f"t_c {res['t_c']:.3e} s  w_ref/w_s {w_ratio:+.3f}: "
                  + " ".join("   FAIL" if res[m] is None else f"{100 * res[m]['spin']:7.2f}" for m in methods),
                  flush=True)
        if args.keep:
            shutil.copytree(tmp, args.keep, dirs_exist_ok=True)

    print(f"\n{len(cases)} cases in {time.monotonic() - start:.0f} s. Spin: worst and median error (relative; "
          "in units of w_s); rebound velocity: worst relative error")
    print("| method | spin: worst | worst case | median | spin/w_s: worst | v_t: worst | v_n: worst "
          "| evaluations per particle | failed |")
    print("|---|---|---|---|---|---|---|---|---|")
    for m in methods:
        done = [(case, res[m]) for case, res in table if res[m] is not None]
        failed = len(table) - len(done)
        if not done:
            print(f"| {labels[m]} | | | | | | | | {failed} |")
            continue
        case, worst = max(done, key=lambda cr: cr[1]["spin"])
        evals = [r["evals"] for _, r in done]
        print(f"| {labels[m]} | {100 * worst['spin']:.1f} % | {' '.join(map(str, case[:3]))} ratio {case[3]:g} "
              f"approach {case[4]:g} | {100 * statistics.median(r['spin'] for _, r in done):.2f} % | "
              f"{100 * max(r['spin_ws'] for _, r in done):.1f} % | {100 * max(r['vt'] for _, r in done):.1f} % | "
              f"{100 * max(r['vn'] for _, r in done):.1f} % | {min(evals):.0f}-{max(evals):.0f} | {failed} |")

    print("\nWorst relative spin error (%) of each pair of laws over set-ups, ratios and approaches (F: failed runs)")
    laws = list(dict.fromkeys(case[1:3] for case, _ in table))
    print("| laws | " + " | ".join(labels[m] for m in methods) + " |")
    print("|---|" + "---|" * len(methods))
    for law in laws:
        cells = []
        for m in methods:
            errors = [res[m]["spin"] for case, res in table if case[1:3] == law and res[m] is not None]
            failed = sum(1 for case, res in table if case[1:3] == law and res[m] is None)
            cells.append((f"{100 * max(errors):.1f}" if errors else "") + (f" F{failed}" if failed else ""))
        print(f"| {' + '.join(law)} | " + " | ".join(cells) + " |")

    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["geometry", "normal", "tangential", "ratio", "approach", "friction", "poisson", "young",
                        "speed", "t_c", "wy_ref", "vx_ref", "vz_ref", "w_s", "method", "spin_err", "spin_err_ws",
                        "vt_err", "vn_err", "evals_per_particle"])
            for case, res in table:
                for m in methods:
                    r = res[m] or dict.fromkeys(["spin", "spin_ws", "vt", "vn", "evals"], "fail")
                    w.writerow(list(case) + [args.friction, args.poisson, args.young, args.speed, res["t_c"],
                                             res["wy"], res["vx"], res["vz"], res["w_s"], labels[m], r["spin"],
                                             r["spin_ws"], r["vt"], r["vn"], r["evals"]])
    if args.failed:
        if args.failures:
            pathlib.Path(args.failures).write_text("\n\n".join(args.failed) + "\n")
        print(f"{len(args.failed)} runs stopped with a numerical failure"
              + (f": their scenarios are in {args.failures}" if args.failures else " (--failures FILE keeps them)"))


if __name__ == "__main__":
    main()
