#!/usr/bin/env python3
"""Single-grain settling in still water: runs examples/settling/quartz_{0.1mm,1mm,1cm}.toml
with tsubu, compares the speed with the smooth-sphere terminal speed (Schiller-Naumann drag,
solved by bisection) and an RK4 solution of the same equation of motion with the added mass,
marks Rubey's settling speed, and writes docs/validation/settling.png and settling.csv.

    /usr/bin/python3 validation/settling.py [--tsubu build/tsubu] [--out docs/validation]
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RHO_P, RHO_F, NU, G, C_M = 2650.0, 1000.0, 1e-6, 9.81, 0.5
CASES = [("0.1mm", 1e-4), ("1mm", 1e-3), ("1cm", 1e-2)]


def cd(re):
    return 24 / re * (1 + 0.15 * re ** 0.687) if re <= 1000 else 0.44


class Sphere:
    def __init__(self, d):
        self.d = d
        self.volume = math.pi * d ** 3 / 6
        self.area = math.pi * d ** 2 / 4
        self.m = RHO_P * self.volume

    def drag(self, v):
        return 0.5 * cd(v * self.d / NU) * RHO_F * self.area * v * v if v > 0 else 0.0

    def weight(self):
        return (self.m - RHO_F * self.volume) * G

    def accel(self, v):
        return (self.weight() - self.drag(v)) / (self.m + C_M * RHO_F * self.volume)


def terminal_speed(s):
    lo, hi = 0.0, 100.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if s.drag(mid) < s.weight():
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def rubey(d):
    s1 = RHO_P / RHO_F - 1
    dstar = s1 * G * d ** 3 / NU ** 2
    return math.sqrt(s1 * G * d) * (math.sqrt(2 / 3 + 36 / dstar) - math.sqrt(36 / dstar))


def rk4(s, times, substeps=50):
    """Downward speed at the given (increasing) times, from rest at t = 0: classical RK4
    with `substeps` steps between consecutive times."""
    v, t, out = 0.0, 0.0, []
    for t_end in times:
        h = (t_end - t) / substeps
        for _ in range(substeps if t_end > t else 0):
            k1 = s.accel(v)
            k2 = s.accel(v + 0.5 * h * k1)
            k3 = s.accel(v + 0.5 * h * k2)
            k4 = s.accel(v + h * k3)
            v += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t = t_end
        out.append(v)
    return out


def run_case(tsubu, name, workdir):
    scenario = os.path.join(ROOT, "examples", "settling", f"quartz_{name}.toml")
    out = os.path.join(workdir, name)
    subprocess.run([tsubu, "run", scenario, "--out", out], check=True, stdout=subprocess.DEVNULL)
    times, speeds = [], []
    with open(os.path.join(out, "track.csv")) as f:
        for row in csv.DictReader(f):
            times.append(float(row["time"]))
            speeds.append(-float(row["vz"]))
    return times, speeds


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "validation"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    rows = []
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.3))
    with tempfile.TemporaryDirectory() as work:
        for ax, (name, d) in zip(axes, CASES):
            s = Sphere(d)
            ut, ur = terminal_speed(s), rubey(d)
            t, v = run_case(args.tsubu, name, work)
            ref = rk4(s, t)
            worst = max(abs(a - b) for a, b in zip(v, ref)) / ut
            rows.append({
                "case": name, "d_m": d, "terminal_m_s": ut, "re_terminal": ut * d / NU, "engine_final_m_s": v[-1],
                "terminal_error": abs(v[-1] - ut) / ut, "transient_max_error_of_ut": worst,
                "rubey_m_s": ur, "rubey_over_terminal": ur / ut, "time_scale_s": ut / s.accel(0.0),
            })
            t_ms = [x * 1e3 for x in t]
            ax.plot(t_ms, v, color="C0", lw=2, label="tsubu")
            ax.plot(t_ms, ref, color="k", lw=1, ls="--", label="RK4 reference (added mass)")
            ax.axhline(ut, color="C2", lw=1, label=f"terminal $u_t$ = {ut:.4g} m/s")
            ax.axhline(ur, color="C3", lw=1, ls=":", label=f"Rubey $u_r$ = {ur:.4g} m/s")
            ax.set_title(f"quartz, d = {name} (Re$_t$ = {ut * d / NU:.4g})")
            ax.set_xlabel("time (ms)")
            ax.set_ylabel("settling speed (m/s)")
            ax.set_ylim(0, 1.12 * max(ut, ur))
            ax.legend(loc="lower right", fontsize=8)
            ax.grid(alpha=0.3)
    fig.suptitle("Single quartz sphere released from rest in still water (rho_f = 1000, nu = 1e-6)")
    fig.tight_layout()
    png = os.path.join(args.out, "settling.png")
    fig.savefig(png, dpi=120)
    with open(os.path.join(args.out, "settling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: x if isinstance(x, str) else f"{x:.6g}" for k, x in r.items()})
    print("| d | u_t (bisection) | Re_t | tsubu final | error | transient max err / u_t | Rubey u_r | u_r/u_t |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['case']} | {r['terminal_m_s']:.5f} m/s | {r['re_terminal']:.4g} | {r['engine_final_m_s']:.5f} m/s"
              f" | {r['terminal_error']:.1e} | {r['transient_max_error_of_ut']:.1e} | {r['rubey_m_s']:.4f} m/s"
              f" | {r['rubey_over_terminal']:.3f} |")
    print(f"wrote {png}", file=sys.stderr)


if __name__ == "__main__":
    main()
