#!/usr/bin/env python3
"""Rolling resistance: runs examples/rolling/rolling_sphere.toml (model CDT) for several
coefficients mu_r and examples/rolling/incline.toml (model EPSD) for several slopes with
tsubu, compares them with the analytic solutions of a rolling solid sphere, and writes
docs/validation/rolling-resistance.png and rolling-resistance.csv.

    /usr/bin/python3 validation/rolling_resistance.py [--tsubu build/tsubu] [--out docs/validation]
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
from report_files import save  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = os.path.join(ROOT, "examples", "rolling")
G, V0, R = 9.81, 0.1, 0.005
E, NU, RHO = 1e8, 0.2, 2500.0
MU_R_EPSD = 0.1


def run(tsubu, scenario, sets, folder):
    """Runs the scenario with --set overrides; returns the tracked rows (time, x, vx)."""
    args = [tsubu, "run", os.path.join(EXAMPLES, scenario), "--out", folder]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(folder, "track.csv")) as f:
        return [(float(r["time"]), float(r["x"]), float(r["vx"])) for r in csv.DictReader(f)]


def slope(points):
    n = len(points)
    st = sum(t for t, _ in points)
    sv = sum(v for _, v in points)
    stt = sum(t * t for t, _ in points)
    stv = sum(t * v for t, v in points)
    return (n * stv - st * sv) / (n * stt - st * st)


def rolling_stiffness_deflection(theta):
    """R M / k_r: how far the centre moves while the EPSD spring takes up the wall's torque
    M = R m g sin(theta), with k_r = 2.25 k_n mu_r^2 R^2 and k_n = 2 E* sqrt(R delta) at the
    static overlap of Hertz."""
    e_star = 1 / (2 * (1 - NU * NU) / E)
    m = RHO * math.pi / 6 * (2 * R) ** 3
    load = m * G * math.cos(theta)
    delta = (3 * load / (4 * e_star * math.sqrt(R))) ** (2 / 3)
    k_r = 2.25 * 2 * e_star * math.sqrt(R * delta) * (MU_R_EPSD * R) ** 2
    return R * (R * m * G * math.sin(theta)) / k_r


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tsubu", default=os.path.join(ROOT, "build", "tsubu"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "validation"))
    opts = ap.parse_args()
    rows = []
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    with tempfile.TemporaryDirectory() as tmp:
        for k, mu_r in enumerate([0.02, 0.05, 0.1]):
            a = 5 / 7 * mu_r * G
            t_stop, x_stop = V0 / a, V0 * V0 / (2 * a)
            track = run(opts.tsubu, "rolling_sphere.toml",
                        [f"contact.default.rolling_friction={mu_r}", f"simulation.duration={1.2 * t_stop:.4f}"],
                        os.path.join(tmp, f"cdt{k}"))
            fit = slope([(t, v) for t, _, v in track if 0.05 <= t <= 0.8 * t_stop])
            stop = next(r for r in track if r[2] <= 0)
            rows += [["cdt", mu_r, "", "deceleration (m/s^2)", -fit, a], ["cdt", mu_r, "", "stop distance (m)", stop[1], x_stop],
                     ["cdt", mu_r, "", "stop time (s)", stop[0], t_stop]]
            print(f"CDT mu_r = {mu_r}: deceleration {-fit:.5f} m/s^2 (analytic {a:.5f}), stops after "
                  f"{stop[1] * 1e3:.3f} mm at {stop[0]:.3f} s (analytic {x_stop * 1e3:.3f} mm, {t_stop:.3f} s)")
            line = left.plot([t for t, _, _ in track], [v for _, _, v in track], lw=2, alpha=0.6, label=f"tsubu, μ_r = {mu_r}")
            ts = [t_stop * i / 50 for i in range(51)]
            left.plot(ts, [V0 - a * t for t in ts], "k--", lw=0.8, label="analytic: v0 − 5/7 μ_r g t" if k == 0 else None)
            left.plot([t_stop], [0], "o", color=line[0].get_color())
        for k, tan_theta in enumerate([0.04, 0.08, 0.12, 0.16]):
            theta = math.atan(tan_theta)
            gravity = f"simulation.gravity=[{G * math.sin(theta)!r}, 0, {-G * math.cos(theta)!r}]"
            track = run(opts.tsubu, "incline.toml", [gravity], os.path.join(tmp, f"epsd{k}"))
            times = [t for t, _, _ in track]
            xs = [x for _, x, _ in track]
            if tan_theta < MU_R_EPSD:
                bound = rolling_stiffness_deflection(theta)
                late = [x for t, x, _ in track if t >= 0.15]
                rows += [["epsd", MU_R_EPSD, tan_theta, "displacement at rest (m); analytic: R M/k_r", xs[-1], bound],
                         ["epsd", MU_R_EPSD, tan_theta, "creep over the last 0.15 s (m)", max(late) - min(late), 0]]
                print(f"EPSD tan(theta) = {tan_theta}: held, moved {xs[-1]:.3e} m (R M/k_r = {bound:.3e} m), "
                      f"{max(late) - min(late):.1e} m over the last 0.15 s")
                right.plot(times, [x * 1e3 for x in xs], lw=2, label=f"tsubu, tan θ = {tan_theta} (held)")
            else:
                a = 5 / 7 * G * (math.sin(theta) - MU_R_EPSD * math.cos(theta))
                fit = slope([(t, v) for t, _, v in track if t >= 0.1])
                rows.append(["epsd", MU_R_EPSD, tan_theta, "acceleration (m/s^2)", fit, a])
                print(f"EPSD tan(theta) = {tan_theta}: rolls, acceleration {fit:.5f} m/s^2 (analytic {a:.5f})")
                right.plot(times, [x * 1e3 for x in xs], lw=2, alpha=0.6, label=f"tsubu, tan θ = {tan_theta} (rolls)")
                right.plot(times, [0.5 * a * t * t * 1e3 for t in times], "k--", lw=0.8,
                           label="analytic: ½ · 5/7 g (sin θ − μ_r cos θ) t²" if tan_theta == 0.12 else None)
    left.set_xlabel("time (s)")
    left.set_ylabel("speed along x (m/s)")
    left.set_title("CDT: a sphere rolling on a floor stops (dots: analytic stop)")
    left.set_ylim(bottom=-0.005)
    left.legend(fontsize=8)
    right.set_xlabel("time (s)")
    right.set_ylabel("displacement down the slope (mm)")
    right.set_title(f"EPSD, μ_r = {MU_R_EPSD}: a sphere on an incline from rest")
    right.legend(fontsize=8)
    save(fig, opts.out, "rolling-resistance", ["model", "mu_r", "tan_theta", "quantity", "tsubu", "analytic"], rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
