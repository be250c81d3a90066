#!/usr/bin/env python3
"""Silo discharge against the Beverloo correlation: the flat-bottomed silo of
examples/silo/silo.toml (about 9000 glass beads of d = 2 mm in a cylinder of 40 mm diameter)
discharges through a circular outlet of diameter D = 8, 10, 12 and 14 mm. Each run's steady
mass flow rate W is the slope of the mass gone through the outlet (outflow.csv) against time,
from 0.1 s after the plug drops (t = 0.5 s) until a third of the beads have left or the run
ends, with the standard error of the slope from four blocks of that window. Beverloo,
Leniger and van de Velde (1961):

    W = C rho_b sqrt(g) (D - k d)^(5/2),

rho_b the bulk density of the bed when the outlet opens (the beads' mass over the volume
they fill, measured in the frame at t = 0.4 s). W^(2/5) is linear in D: a straight-line fit
gives C from its slope and k from its intercept, with their standard errors; the accepted
ranges are C = 0.55-0.65 and k = 1.3-1.6 (Nedderman 1992). Writes docs/validation/beverloo.png
and beverloo.csv.

    PYTHONPATH=build/python /usr/bin/python3 validation/beverloo.py [--jobs 2] [--tsubu build/tsubu]
    PYTHONPATH=build/python /usr/bin/python3 validation/beverloo.py --quick   # one outlet, half the beads (CTest)

Runs go to out/validation/beverloo/ (a finished run is reused); about 5 minutes each on one core.
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENARIO = os.path.join(ROOT, "examples", "silo", "silo.toml")
OUTLETS = (0.008, 0.010, 0.012, 0.014)  # m, diameters
D_GRAIN = 0.002
RHO_S = 2500.0
G = 9.81
SILO_RADIUS = 0.02
T_OPEN = 0.4  # s, when the plug starts to drop (silo.toml)
SETTLE = 0.1  # s after it, before the flow is steady
BLOCKS = 4


def run_case(tsubu, out, outlet, duration, sets=()):
    if os.path.isfile(os.path.join(out, "run.json")):
        with open(os.path.join(out, "run.json")) as f:
            if json.load(f).get("status") == "ok":
                return out
    cmd = [tsubu, "run", SCENARIO, "--out", out, "--overwrite", "--set", f"walls.1.hole_radius={outlet / 2:g}",
           "--set", f"simulation.duration={duration:g}"] + [a for v in sets for a in ("--set", v)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return out


def discharge_rate(out, total_mass):
    """(W, its standard error, window start, window end) from outflow.csv."""
    from tsubu.runs import read_run
    run = read_run(out)
    t, m = np.asarray(run.outflow["time"], float), np.cumsum(np.asarray(run.outflow["mass"], float))
    start = T_OPEN + SETTLE
    end = min(t[-1], t[np.searchsorted(m, total_mass / 3)] if m[-1] > total_mass / 3 else t[-1])
    inside = (t >= start) & (t <= end)
    slope = np.polyfit(t[inside], m[inside], 1)[0]
    edges = np.linspace(start, end, BLOCKS + 1)
    blocks = []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (t >= a) & (t <= b)
        blocks.append(np.polyfit(t[sel], m[sel], 1)[0])
    return slope, np.std(blocks, ddof=1) / math.sqrt(BLOCKS), start, end


def bulk_density(out):
    """The beads' mass over the volume they fill at the outlet's opening: the silo's section
    times the bed's height (the mean height of its top layer, the highest 5 % of the
    centres, plus a radius)."""
    from tsubu.runs import read_run
    run = read_run(out)
    i = int(np.argmin(np.abs(np.asarray(run.frames.times) - T_OPEN)))
    frame = run.frame(i)
    z = frame.points[:, 2]
    d = np.asarray(frame["diameter"], float)
    mass = np.sum(RHO_S * math.pi / 6 * d ** 3)
    height = np.mean(np.sort(z)[-max(1, len(z) // 20):]) + 0.5 * D_GRAIN
    return mass / (math.pi * SILO_RADIUS ** 2 * height), mass, len(z)


def beverloo_fit(D, W, W_err):
    """C and k with standard errors, from W^(2/5) = A (D - k d), weighted by W's errors."""
    y = W ** 0.4
    sy = 0.4 * W ** -0.6 * W_err
    w = 1 / sy ** 2
    X = np.vstack([D, np.ones_like(D)]).T
    cov = np.linalg.inv(X.T @ (X * w[:, None]))
    slope, intercept = cov @ (X.T @ (w * y))
    # The scatter about the line, if larger than the errors say, widens them.
    chi2 = np.sum(w * (y - (slope * D + intercept)) ** 2) / (len(D) - 2)
    cov = cov * max(1.0, chi2)
    return slope, intercept, cov


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--runs", default=os.path.join(ROOT, "out", "validation", "beverloo"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "validation"))
    ap.add_argument("--quick", action="store_true", help="one outlet (12 mm), half the beads, to 0.65 s, checked loosely")
    args = ap.parse_args()
    outlets = (0.012,) if args.quick else OUTLETS
    duration = 0.65 if args.quick else 1.0
    # The quick case pours half the beads (a bed of about 1.3 silo diameters still).
    sets = ("particles.0.upper=[0.014, 0.014, 0.08]",) if args.quick else ()
    runs = {D: os.path.join(args.runs, ("quick_" if args.quick else "") + f"D{D * 1e3:g}mm") for D in outlets}
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        list(pool.map(lambda D: run_case(args.tsubu, runs[D], D, duration, sets), outlets))
    rows = []
    for D in outlets:
        rho_b, mass, grains = bulk_density(runs[D])
        W, W_err, start, end = discharge_rate(runs[D], mass)
        beverloo = 0.58 * rho_b * math.sqrt(G) * (D - 1.5 * D_GRAIN) ** 2.5
        rows.append(dict(D=D, W=W, W_err=W_err, rho_b=rho_b, grains=grains, start=start, end=end, beverloo=beverloo))
        print(f"D = {D * 1e3:g} mm: W = {W * 1e3:.2f} +- {W_err * 1e3:.2f} g/s (t = {start:.2f}-{end:.2f} s), "
              f"rho_b = {rho_b:.0f} kg/m^3, Beverloo with C = 0.58, k = 1.5: {beverloo * 1e3:.2f} g/s")
    if args.quick:
        r = rows[0]
        ratio = r["W"] / r["beverloo"]
        # C = 0.55-0.65 and k = 1.3-1.6 bound W at D = 6 d between these multiples of C = 0.58, k = 1.5.
        low = 0.55 / 0.58 * ((6 - 1.6) / 4.5) ** 2.5
        high = 0.65 / 0.58 * ((6 - 1.3) / 4.5) ** 2.5
        print(f"W / Beverloo(0.58, 1.5) = {ratio:.3f}; the accepted ranges allow {low:.3f}-{high:.3f}")
        sys.exit(0 if 0.7 * low <= ratio <= 1.3 * high else 1)
    D = np.array([r["D"] for r in rows])
    W = np.array([r["W"] for r in rows])
    W_err = np.array([r["W_err"] for r in rows])
    rho_b = float(np.mean([r["rho_b"] for r in rows]))
    slope, intercept, cov = beverloo_fit(D, W, W_err)
    C = slope ** 2.5 / (rho_b * math.sqrt(G))
    C_err = 2.5 * slope ** 1.5 * math.sqrt(cov[0, 0]) / (rho_b * math.sqrt(G))
    k = -intercept / (slope * D_GRAIN)
    # k = -b/(a d): its variance from a, b and their covariance.
    dk_da, dk_db = intercept / (slope ** 2 * D_GRAIN), -1 / (slope * D_GRAIN)
    k_err = math.sqrt(dk_da ** 2 * cov[0, 0] + dk_db ** 2 * cov[1, 1] + 2 * dk_da * dk_db * cov[0, 1])
    print(f"fit W^(2/5) = A (D - k d): C = {C:.3f} +- {C_err:.3f}, k = {k:.2f} +- {k_err:.2f} (rho_b = {rho_b:.0f} kg/m^3)")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "beverloo.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["D_m", "W_kg_s", "W_standard_error", "rho_b", "grains", "window_start_s", "window_end_s",
                    "beverloo_C0.58_k1.5", "fit_C", "fit_C_err", "fit_k", "fit_k_err"])
        for r in rows:
            w.writerow([r["D"], r["W"], r["W_err"], r["rho_b"], r["grains"], r["start"], r["end"], r["beverloo"],
                        C, C_err, k, k_err])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    Ds = np.linspace(0.007, 0.015, 100)
    for c, kk, style in ((0.55, 1.6, ":"), (0.65, 1.3, ":")):
        ax.plot(Ds * 1e3, c * rho_b * math.sqrt(G) * np.clip(Ds - kk * D_GRAIN, 0, None) ** 2.5 * 1e3, "0.5",
                ls=style, lw=1)
    ax.fill_between(Ds * 1e3, 0.55 * rho_b * math.sqrt(G) * np.clip(Ds - 1.6 * D_GRAIN, 0, None) ** 2.5 * 1e3,
                    0.65 * rho_b * math.sqrt(G) * np.clip(Ds - 1.3 * D_GRAIN, 0, None) ** 2.5 * 1e3, color="0.85",
                    label="Beverloo, C = 0.55-0.65, k = 1.3-1.6")
    ax.plot(Ds * 1e3, C * rho_b * math.sqrt(G) * np.clip(Ds - k * D_GRAIN, 0, None) ** 2.5 * 1e3, "tab:red",
            label=f"fit: C = {C:.2f} ± {C_err:.2f}, k = {k:.2f} ± {k_err:.2f}")
    ax.errorbar(D * 1e3, W * 1e3, yerr=2 * W_err * 1e3, fmt="ko", capsize=3, label="tsubu (2 standard errors)")
    ax.set_xlabel("outlet diameter D (mm)")
    ax.set_ylabel("mass flow rate W (g/s)")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    from tsubu.runs import read_run
    for Dv in outlets:
        run = read_run(runs[Dv])
        ax2.plot(run.outflow["time"], np.cumsum(run.outflow["mass"]) * 1e3, label=f"D = {Dv * 1e3:g} mm")
    ax2.axvspan(T_OPEN, T_OPEN + SETTLE, color="0.9")
    ax2.set_xlabel("t (s)")
    ax2.set_ylabel("mass discharged (g)")
    ax2.legend(fontsize="small")
    ax2.grid(alpha=0.3)
    fig.suptitle(f"Silo discharge (examples/silo/silo.toml, d = {D_GRAIN * 1e3:g} mm, silo 40 mm) against Beverloo")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "beverloo.png"), dpi=110)
    print(f"wrote {os.path.join(args.out, 'beverloo.png')} and beverloo.csv")


if __name__ == "__main__":
    main()
