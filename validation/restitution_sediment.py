#!/usr/bin/python3
"""The restitution coefficient of Sota & Watanabe's contact law (model H, hertz_sediment)
against the impact speed, for both readings of its Eq. 14 (docs/engine.md, "Sota &
Watanabe's contact law, read both ways"): the dashpot as printed, eta = alpha sqrt(K m*
dbar^{1/2}) (dashpot = "constant"), and in Tsuji's form, eta = alpha sqrt(K m* delta^{1/2})
(dashpot = "tsuji"); alpha = 0.2 and the paper's Table 1 quartz (E = 1 GPa, sigma = 0.17).

Each point is a head-on collision of two equal grains in vacuum, without gravity, run by the
engine itself (the Python module, velocity Verlet at 1/400 of the Hertz contact time):
e = (relative speed after) / (relative speed before). Grain diameters: the paper's largest
(1 cm) and its mixtures' smallest (1.25 and 0.63 mm); impact speeds 1 mm/s to 1 m/s,
those of the experiment (the grains' terminal speeds in water are 0.1-0.7 m/s, and
settling grains meet at far less).

    /usr/bin/python3 validation/restitution_sediment.py [--out DIR] [--quick]

Writes restitution-sediment.csv and restitution-sediment.png to DIR (default
docs/validation). --quick checks three points and exits 1 if the Tsuji reading's
restitution differs from the closed form e(alpha = 0.2) = 0.754 by more than 0.002 or the
constant dashpot's is not below it at 0.1 m/s (CTest runs it). About 30 s in full.
"""
import argparse
import math
import sys
import tempfile
from pathlib import Path

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as exc:  # CTest: SKIP_RETURN_CODE 77
    print(f"skipped: {sys.executable} cannot import numpy and matplotlib ({exc})")
    sys.exit(77)

import tsubu

E, SIGMA, RHO, ALPHA = 1e9, 0.17, 2650.0, 0.2
SCENARIO = """
[simulation]
duration = {duration}
dt = {dt}
integrator = "velocity_verlet"
gravity = [0, 0, 0]

[domain]
lower = [-{box}, -{box}, -{box}]
upper = [{box}, {box}, {box}]

[[materials]]
name = "quartz"
density = {rho}
youngs_modulus = {E}
poisson = {sigma}

[contact.default]
normal = "hertz_sediment"
tangential = "none"
alpha = {alpha}
dashpot = "{dashpot}"

[[particles]]
source = "csv"
material = "quartz"
file = "{csv}"
"""


def hertz_contact_time(d, u):
    """Sota & Watanabe Eq. 20 for two equal grains: 2.94 (m*^2 / (K^2 u))^{1/5}."""
    e_star = E / (2 * (1 - SIGMA**2))
    r_eff, m_eff = d / 4, RHO * math.pi * d**3 / 12
    k = 4 / 3 * e_star * math.sqrt(r_eff)
    return 2.94 * (m_eff**2 / (k**2 * u)) ** 0.2


def restitution(d, u, dashpot, folder):
    """Two grains of diameter d meeting head-on at relative speed u."""
    gap = 0.01 * d
    csv = Path(folder) / "pair.csv"
    csv.write_text(f"x,y,z,d,vx,vy,vz\n{-0.5 * (d + gap)},0,0,{d},{u / 2},0,0\n{0.5 * (d + gap)},0,0,{d},{-u / 2},0,0\n")
    t_c = hertz_contact_time(d, u)
    dt = t_c / 400
    # The approach, then the contact until the grains part. A strong constant dashpot pulls
    # the parting grains together (its force turns attractive), so that they may part only
    # very slowly: after 20 contact times the relative speed then is taken as it stands.
    approach = gap / u
    sim = tsubu.Simulation(SCENARIO.format(duration=approach + 20 * t_c, dt=dt, box=4 * d, rho=RHO, E=E, sigma=SIGMA,
                                           alpha=ALPHA, dashpot=dashpot, csv=csv))
    sim.advance_to(approach + 0.5 * t_c)
    while len(sim.contacts()["i"]) and sim.time + t_c / 4 <= sim.duration:
        sim.advance_to(sim.time + t_c / 4)
    v = sim.velocities[:, 0]
    order = np.argsort(sim.positions[:, 0])
    return (v[order[1]] - v[order[0]]) / u


def tsuji_closed_form(alpha):
    """The restitution of Tsuji's dashpot: alpha = sqrt(5) |ln e| / sqrt(ln^2 e + pi^2)."""
    a = alpha / math.sqrt(5)
    return math.exp(-math.pi * a / math.sqrt(1 - a * a))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "validation"))
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        if args.quick:
            e_t = [restitution(0.01, u, "tsuji", folder) for u in (0.01, 0.5)]
            e_c = restitution(0.01, 0.1, "constant", folder)
            ref = tsuji_closed_form(ALPHA)
            failures = [f"tsuji e = {e:.4f}, expected {ref:.4f}" for e in e_t if abs(e - ref) > 0.002]
            if not e_c < ref - 0.1:
                failures.append(f"constant dashpot e = {e_c:.4f} at 0.1 m/s, expected well below {ref:.4f}")
            print(f"tsuji: {e_t}, constant at 0.1 m/s: {e_c:.4f}, closed form {ref:.4f}")
            if failures:
                print("\n".join(failures))
                sys.exit(1)
            return
        speeds = np.logspace(-3, 0, 13)
        rows = []
        for d in (0.01, 0.00125, 0.000625):
            for dashpot in ("constant", "tsuji"):
                for u in speeds:
                    rows.append((d, dashpot, u, restitution(d, u, dashpot, folder)))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "restitution-sediment.csv", "w") as f:
        f.write("d_m,dashpot,impact_speed_m_s,restitution\n")
        for d, dashpot, u, e in rows:
            f.write(f"{d},{dashpot},{u:.6g},{e:.5f}\n")
    fig, ax = plt.subplots(figsize=(6, 4))
    for d, colour in zip((0.01, 0.00125, 0.000625), ("C0", "C1", "C2")):
        for dashpot, style in (("constant", "-o"), ("tsuji", "--s")):
            pts = [(u, e) for dd, dp, u, e in rows if dd == d and dp == dashpot]
            ax.semilogx(*zip(*pts), style, color=colour, ms=3,
                        label=f"d = {d * 1000:g} mm, {'Eq. 14 as printed' if dashpot == 'constant' else 'Tsuji form'}")
    ax.axhline(tsuji_closed_form(ALPHA), color="grey", lw=0.8, ls=":")
    ax.set_xlabel("impact speed (m/s)")
    ax.set_ylabel("restitution coefficient e")
    ax.set_ylim(0, 1)
    ax.set_title("Model H, alpha = 0.2, E = 1 GPa: two equal quartz grains")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "restitution-sediment.png", dpi=120)
    print(f"wrote {out / 'restitution-sediment.csv'} and .png")


if __name__ == "__main__":
    main()
