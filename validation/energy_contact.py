#!/usr/bin/python3
"""Validation of the energy-conserving normal contact (spec/validation.md, cases A1-A5).

Runs the scenarios of examples/energy-contact/ with the tsubu binary for the four normal
models C (linear), T (hertz_tsuji), F (energy_conserving_2005, reconstructed) and
P (energy_conserving), and writes csv tables and png figures in the style of the paper's
Figs. 4, 5, 6/7, 10, 11 and Tables 1-2 to validation/results/energy-contact/.

    /usr/bin/python3 validation/energy_contact.py [TSUBU] [--out DIR] [--quick]

TSUBU is the binary (default: $TSUBU, else build/tsubu). The full run takes about a quarter
of an hour on one core, most of it in the 5e6-step cost case (A4). --quick runs reduced
versions (A4 for 1e5 steps, A5 only at dt = 1e-5, A2 only the first contact), checks the
spec's tolerances and exits 1 with a message naming every failed check; by default it
writes to a temporary folder that is removed afterwards. Exit 77 when numpy or matplotlib
is missing (CTest counts it as skipped).

Definitions (docs/validation/energy-contact.md):
- k_n and E are fixed per case at dt = 1e-3 (model C's contact lasts 10 steps, T's 14) and,
  in the dt sweeps, scaled by (1e-3/dt)^2 so that a = k_n dt^2/m* stays fixed ("scaled",
  the paper's convention, which reproduces its Table 2 and Figs. 10-11); the sweeps are
  also run with the dt = 1e-3 values kept ("fixed").
- Apex energy of a flight: H = v^2/2 + g h - g dt v/2 per unit mass (h: height of the lowest
  point above the wall), which symplectic Euler keeps exactly in free flight and which is
  the energy at the apex (v = 0). The energy ratio of bounce N is H_N / H_{N-1}.
- Collision energy ratio (the paper's wording, "before and after the N-th collision"):
  E = v^2/2 + g h at the last free state before the contact and the first one after it.
- Phase space of a contact step: d = delta/d_c, u = p + q = -v_n dt/d_c, s = u/d, with
  delta taken before model P's contact-step position correction.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as exc:  # CTest: SKIP_RETURN_CODE 77
    print(f"skipped: {sys.executable} cannot import numpy and matplotlib ({exc})")
    sys.exit(77)

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

REPO = Path(__file__).resolve().parent.parent
EXAMPLES = REPO / "examples" / "energy-contact"
RESULTS = REPO / "validation" / "results" / "energy-contact"

MODELS = ["C", "T", "F", "P"]
NORMAL = {"C": "linear", "T": "hertz_tsuji", "F": "energy_conserving_2005", "P": "energy_conserving"}
STYLE = {
    "C": dict(color="tab:blue", marker="o"),
    "T": dict(color="tab:orange", marker="s"),
    "F": dict(color="tab:green", marker="^"),
    "P": dict(color="tab:red", marker="D"),
}
LABEL = {"C": "C (linear)", "T": "T (Hertz-Tsuji)", "F": "F (reconstructed)", "P": "P (this model)"}
E_REST = 0.7
G = 9.8
DT_REF = 1e-3

# Paper values (Tables 1 and 2) and the exact three-sphere solution (spec, case A5).
PAPER_TABLE2 = {"C": (9, 10, 10), "T": (14, 23, 37), "F": (2, 1, 1), "P": (3, 3, 3)}
PAPER_TABLE1 = {  # total time (s), normal-force time (s), contact evaluations, s per evaluation
    "T": (341, 24, 1.26e7, 1.91e-6),
    "F": (269, 11, 5.62e6, 1.95e-6),
    "C": (423, 35, 1.87e7, 1.88e-6),
    "P": (306, 21, 1.07e7, 1.96e-6),
}
R0 = 0.02
T0_EXACT = math.sqrt(R0 / G) * 2.3627213913  # 0.1067368725 s
V_EXACT = 2.0 * math.sqrt(G * R0) * 0.2714626510  # 0.2403632775 m/s

# Tolerances checked by --quick (spec/validation.md, case A).
TOL_ENERGY = 0.01  # P's energy ratio within 1% of e^2 for every bounce N <= N_CHECK
N_CHECK = 10  # "every bounce" of the slow case: the first ten (impact speed 6.6 -> 0.27 m/s)
TOL_THREE = 0.005  # P's T0 and final speed at dt = 1e-5 within 0.5%
P_STEPS = 3  # P's contact lasts 3 steps at every dt

# Track columns.
TIME, ID, X, Y, Z, VX, VY, VZ = 0, 1, 2, 3, 4, 5, 6, 7
FX, FY, FZ, CONTACTS = 11, 12, 13, 14


def fmt(x):
    return repr(float(x))


# ----------------------------------------------------------------------------- running


class Runner:
    def __init__(self, tsubu, work):
        self.tsubu = tsubu
        self.work = Path(work)
        self.count = 0
        self.seconds = 0.0

    def run(self, scenario, tag, sets=()):
        out = self.work / tag
        if out.exists():
            shutil.rmtree(out)
        cmd = [str(self.tsubu), "run", str(EXAMPLES / scenario), "--out", str(out)]
        for s in sets:
            cmd += ["--set", s]
        env = dict(os.environ, OMP_NUM_THREADS="1")
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
        self.seconds += time.perf_counter() - t0
        self.count += 1
        if proc.returncode not in (0, 3):
            raise RuntimeError(f"{' '.join(cmd)}\nexit {proc.returncode}: {proc.stderr.strip()}")
        info = json.loads((out / "run.json").read_text()) if (out / "run.json").exists() else {}
        return Run(proc.returncode, out, info, proc.stderr.strip())


class Run:
    def __init__(self, rc, out, info, stderr):
        self.rc, self.out, self.info, self.stderr = rc, out, info, stderr

    @property
    def ok(self):
        return self.rc == 0

    def track(self):
        path = self.out / "track.csv"
        if not path.exists():
            return np.zeros((0, 15))
        with open(path) as f:
            next(f)
            rows = [line for line in f if line.strip()]
        if not rows:
            return np.zeros((0, 15))
        return np.loadtxt(rows, delimiter=",", ndmin=2)


def scenario_values(name):
    """dt, stiffness, Young's modulus and the first particle's diameter of a scenario."""
    text = (EXAMPLES / name).read_text()
    if tomllib is not None:
        sc = tomllib.loads(text)
        dt = sc["simulation"]["dt"]
        k = sc["contact"]["default"]["stiffness"]
        E = sc["materials"][0]["youngs_modulus"]
    else:  # minimal reader for the three keys
        vals = {}
        for line in text.splitlines():
            key, _, rest = line.partition("=")
            key = key.strip()
            if key in ("dt", "stiffness", "youngs_modulus") and key not in vals:
                vals[key] = float(rest.split("#")[0])
        dt, k, E = vals["dt"], vals["stiffness"], vals["youngs_modulus"]
    return dt, k, E


def contact_sets(model, k, E):
    """--set values that select one model (the whole [contact.default] table) and E."""
    if model == "T":
        table = '{normal="hertz_tsuji", tangential="none", restitution=0.7}'
    else:
        table = f'{{normal="{NORMAL[model]}", tangential="none", restitution=0.7, stiffness={fmt(k)}}}'
    return [f"contact.default={table}", f"materials.0.youngs_modulus={fmt(E)}"]


def stiffness_at(name, dt, convention):
    """k_n and E of scenario `name` at step dt: 'scaled' keeps a = k dt^2/m* (the values at
    dt = 1e-3 times (1e-3/dt)^2), 'fixed' keeps the values at dt = 1e-3."""
    dt0, k0, E0 = scenario_values(name)
    k_ref, E_ref = k0 * (dt0 / DT_REF) ** 2, E0 * (dt0 / DT_REF) ** 2
    if convention == "fixed":
        return k_ref, E_ref
    return k_ref * (DT_REF / dt) ** 2, E_ref * (DT_REF / dt) ** 2


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(fmt_cell(c) for c in r) + "\n")


def fmt_cell(c):
    if isinstance(c, float):
        if math.isnan(c):
            return ""
        return f"{c:.10g}"
    return str(c)


# ----------------------------------------------------------------------------- analysis


def episodes(contacts):
    """(start, end) index ranges of consecutive rows with contact."""
    on = contacts > 0
    out, i, n = [], 0, len(on)
    while i < n:
        if on[i]:
            j = i
            while j < n and on[j]:
                j += 1
            out.append((i, j))
            i = j
        else:
            i += 1
    return out


def wall_bounces(tr, radius, dt, resting_limit=None):
    """Bounces of one sphere on the wall z = 0 from a track written every step.

    Returns a list of dicts (one per contact) with the contact steps, impact speed, the apex
    energy H of the flights before and after, and E at the free states around the contact."""
    t, z, vz, c = tr[:, TIME], tr[:, Z], tr[:, VZ], tr[:, CONTACTS]
    h = z - radius
    H = 0.5 * vz**2 + G * h - 0.5 * G * dt * vz
    E = 0.5 * vz**2 + G * h
    eps = episodes(c)
    # flight k: free rows after contact k (flight 0 before the first contact)
    bounds = [0] + [e for _, e in eps]
    starts = [s for s, _ in eps] + [len(t)]
    flight_H = []
    for k in range(len(bounds)):
        lo, hi = bounds[k], starts[k]
        free = H[lo:hi][c[lo:hi] == 0]
        flight_H.append((float(np.median(free)) if len(free) else math.nan, hi - lo))
    out = []
    for n, (s, e) in enumerate(eps):
        ended = e < len(t)
        before, after = s - 1, e
        rec = dict(
            N=n + 1,
            t_contact=float(t[s]),
            steps=e - s if ended else math.nan,
            impact_speed=float(-vz[s]),
            H_before=flight_H[n][0],
            H_after=flight_H[n + 1][0] if ended else math.nan,
            flight_after_steps=flight_H[n + 1][1] if ended else 0,
            E_before=float(E[before]) if before >= 0 else math.nan,
            E_after=float(E[after]) if ended else math.nan,
        )
        rec["ratio_apex"] = rec["H_after"] / rec["H_before"]
        rec["ratio_collision"] = rec["E_after"] / rec["E_before"]
        out.append(rec)
    return out


def phase_points(tr, radius, d_c, dt, start, end):
    """(d, u, s) of the contact rows start..end-1, the depth taken before any position
    correction of the contact step (x_n = x_{n-1} + v_n dt)."""
    pts = []
    for n in range(start, end):
        z_pre = tr[n - 1, Z] + tr[n, VZ] * dt if n > 0 else tr[n, Z]
        d = (radius - z_pre) / d_c
        u = -tr[n, VZ] * dt / d_c
        pts.append((d, u, u / d if d > 0 else math.nan))
    return pts


def first_contact_steps(tr):
    eps = episodes(tr[:, CONTACTS])
    if not eps:
        return 0
    s, e = eps[0]
    return e - s


def three_sphere_result(tr):
    """T0 (the first state without contact of C after its last contact with A or B) and the
    final speed of B from a track of B (id 1) and C (id 2) written every step."""
    C = tr[tr[:, ID] == 2]
    B = tr[tr[:, ID] == 1]
    above = C[:, Z] > R0 * 1.0001  # C's contacts with the floor do not count
    on = np.nonzero((C[:, CONTACTS] > 0) & above)[0]
    if len(on) == 0 or on[-1] + 1 >= len(C):
        return math.nan, math.nan
    T0 = float(C[on[-1] + 1, TIME])
    V = float(abs(B[-1, VX]))
    return T0, V


# ----------------------------------------------------------------------------- cases


def case_a1(runner, res, log):
    """A1 slow impact: energy ratio per bounce (Fig. 4)."""
    name = "slow-impact.toml"
    dt, k, E = scenario_values(name)
    d = 225.0
    rows, per_model = [], {}
    for m in MODELS:
        r = runner.run(name, f"a1_{m}", contact_sets(m, k, E))
        if not r.ok:
            log.append(f"A1 {m}: run failed: {r.stderr}")
        b = wall_bounces(r.track(), d / 2, dt)
        per_model[m] = b
        for x in b:
            rows.append([m, x["N"], x["t_contact"], x["impact_speed"], x["steps"], x["flight_after_steps"],
                         x["ratio_apex"], x["ratio_collision"]])
    write_csv(res / "a1_slow_energy_ratio.csv",
              ["model", "N", "t_contact_s", "impact_speed_m_s", "contact_steps", "flight_after_steps",
               "e2_apex", "e2_collision"], rows)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True)
    for ax, key, title in ((axes[0], "ratio_apex", "at the apexes (H)"),
                           (axes[1], "ratio_collision", "just before / after the collision (E)")):
        for m in MODELS:
            pts = [(x["N"], x[key]) for x in per_model[m] if x["flight_after_steps"] >= 3 and not math.isnan(x[key])]
            if pts:
                n, v = zip(*pts)
                ax.plot(n, v, ls=":", lw=0.8, ms=5, mfc="none", label=LABEL[m], **STYLE[m])
        ax.axhline(E_REST**2, color="k", lw=0.8)
        ax.axvspan(0.5, N_CHECK + 0.5, color="0.93", zorder=0)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("bounce N")
        ax.set_ylim(0.3, 0.6)
    axes[0].set_ylabel("energy ratio $e^2$ (theory 0.49)")
    axes[0].legend(fontsize=7, loc="lower left")
    fig.suptitle("A1 slow impact (paper Fig. 4), dt = 1e-3", fontsize=10)
    fig.tight_layout()
    fig.savefig(res / "fig4_slow_energy_ratio.png", dpi=100)
    plt.close(fig)
    return per_model


def case_a2(runner, res, log, quick):
    """A2 fast impact: energy ratio per bounce (Fig. 5), phase space (Figs. 6-7), and what
    happens to each model at 1e5 m/s (the spec) and 7e4 m/s (variant)."""
    name = "fast-impact.toml"
    dt, k, E = scenario_values(name)
    d = 225.0
    radius, d_c = d / 2, d
    mass = 1.0 * math.pi / 6 * d**3
    a = k * dt * dt / mass
    speeds = {"1e5": "fast-impact.csv", "7e4": "fast-impact-7e4.csv"}
    n_fine = 2 if quick else 12  # contacts recorded step by step
    outcome_rows, ratio_rows, phase_rows = [], [], []
    paths = {}  # (speed, model) -> list of contact paths [(d, u, s)...]
    tails = {}  # (speed, model) -> states after a tunnelling contact
    ratios = {}
    for sp, csv in speeds.items():
        for m in MODELS:
            sets = contact_sets(m, k, E) + [f'particles.0.file="{csv}"']
            if quick:
                coarse = None
                samples = None
            else:
                coarse = runner.run(name, f"a2_{sp}_{m}", sets)
                samples = coarse.track()
            # Contacts between coarse samples: an interval in which the velocity does not fall
            # by g dt, or with a sample in contact; adjacent such intervals are one contact.
            groups = []  # (free row before the contact, first row after it)
            if samples is not None and len(samples) > 1:
                dv = np.diff(samples[:, VZ])
                expected = -G * np.diff(samples[:, TIME])
                cs = samples[:, CONTACTS] > 0
                flag = (dv > expected + 1e-9 * np.maximum(1.0, np.abs(samples[:-1, VZ]))) | cs[:-1] | cs[1:]
                i = 0
                while i < len(flag):
                    if flag[i]:
                        j = i
                        while j + 1 < len(flag) and flag[j + 1]:
                            j += 1
                        before = i if not cs[i] else i - 1
                        if before >= 0 and not cs[before]:
                            groups.append((before, j + 1))
                        i = j + 1
                    else:
                        i += 1
            bounce_rows = [b for b, _ in groups]
            # Step-by-step restarts from the free sample before each contact (bit-identical to
            # the coarse run, which is checked); the quick mode runs the first contact only.
            if samples is None or not groups:
                restarts = [(None, None)]
            else:
                restarts = groups[:n_fine]
            contact_paths, fine_bounces, failure = [], [], ""
            for j, (row, row_after) in enumerate(restarts):
                if row is None or row == 0:
                    state_csv = csv
                    span = float(samples[row_after, TIME]) if row_after is not None else 1.0
                else:
                    st = samples[row]
                    fn = runner.work / f"a2_{sp}_{m}_restart{j}.csv"
                    fn.write_text("x,y,z,d,vx,vy,vz\n" + ",".join(fmt(v) for v in (
                        st[X], st[Y], st[Z], d, st[VX], st[VY], st[VZ])) + "\n")
                    state_csv = str(fn)
                    span = float(samples[row_after, TIME] - samples[row, TIME])
                fine = runner.run(name, f"a2_{sp}_{m}_fine{j}", contact_sets(m, k, E) + [
                    f'particles.0.file="{state_csv}"', f"simulation.duration={fmt(span + 0.05)}",
                    "output.track_interval=0", "output.series_interval=0.01"])
                tr = fine.track()
                if row_after is not None and len(tr) > 0:  # the restart must retrace the coarse run
                    later = tr[np.isclose(tr[:, TIME], span, rtol=0, atol=dt / 4)]
                    ref = samples[row_after]
                    if len(later) and not np.allclose(later[0, [Z, VZ]], ref[[Z, VZ]], rtol=1e-12, atol=0):
                        log.append(f"A2 {sp} {m}: restart {j} does not retrace the run "
                                   f"(z {later[0, Z]!r} vs {ref[Z]!r})")
                eps = episodes(tr[:, CONTACTS]) if len(tr) else []
                if eps:
                    s0, e0 = eps[0]
                    contact_paths.append(phase_points(tr, radius, d_c, dt, s0, e0))
                    for pt in contact_paths[-1]:
                        phase_rows.append([sp, m, j + 1, pt[0], pt[1], pt[2], 1])
                    if not fine.ok:  # the next states, with the centre behind the wall plane
                        tail = phase_points(tr, radius, d_c, dt, e0, min(e0 + 3, len(tr)))
                        tails[(sp, m)] = [contact_paths[-1][-1]] + tail
                        for pt in tail:
                            phase_rows.append([sp, m, j + 1, pt[0], pt[1], pt[2], 0])
                    fb = wall_bounces(tr, radius, dt)
                    if fb:
                        if not fine.ok:  # the sphere went through the wall: no rebound to measure
                            fb[0].update(ratio_apex=math.nan, ratio_collision=math.nan, steps=math.nan)
                        fine_bounces.append(fb[0])
                if not fine.ok:
                    failure = classify_failure(fine, tr, radius, j + 1)
                    break
            paths[(sp, m)] = contact_paths
            # apex energy of every flight from the coarse samples
            bounce_list = []
            if samples is not None and len(samples) > 0:
                H = 0.5 * samples[:, VZ] ** 2 + G * (samples[:, Z] - radius) - 0.5 * G * dt * samples[:, VZ]
                ends = np.array([a for _, a in groups], dtype=float)
                flight = np.searchsorted(ends - 0.5, np.arange(len(samples)))  # contacts before each row
                free = samples[:, CONTACTS] == 0
                Hf = [float(np.median(H[(flight == f) & free])) if np.any((flight == f) & free) else math.nan
                      for f in range(len(groups) + 1)]
                counts = [int(np.sum((flight == f) & free)) for f in range(len(groups) + 1)]
                for n in range(len(bounce_rows)):
                    if counts[n + 1] < 3:  # flights shorter than the sampling: bounces no longer resolved
                        break
                    bounce_list.append(Hf[n + 1] / Hf[n])
            if not failure and coarse is not None and not coarse.ok:
                failure = classify_failure(coarse, samples, radius, len(bounce_rows) + 1)
            ratios[(sp, m)] = bounce_list
            for n, rr in enumerate(bounce_list):
                fb = fine_bounces[n] if n < len(fine_bounces) else {}
                ratio_rows.append([sp, m, n + 1, rr, fb.get("ratio_collision", math.nan), fb.get("steps", math.nan),
                                   fb.get("impact_speed", math.nan)])
            if quick:
                for n, fb in enumerate(fine_bounces):
                    ratio_rows.append([sp, m, n + 1, math.nan, fb.get("ratio_collision", math.nan),
                                       fb.get("steps", math.nan), fb.get("impact_speed", math.nan)])
            first = fine_bounces[0] if fine_bounces else {}
            max_d = max((p[0] for p in contact_paths[0]), default=math.nan) if contact_paths else math.nan
            outcome_rows.append([sp, m, len(bounce_list), failure or "ok", first.get("ratio_collision", math.nan),
                                 max_d])
    write_csv(res / "a2_fast_outcome.csv",
              ["speed_m_s", "model", "bounces", "outcome", "first_e2_collision", "first_contact_max_d"], outcome_rows)
    write_csv(res / "a2_fast_energy_ratio.csv",
              ["speed_m_s", "model", "N", "e2_apex", "e2_collision", "contact_steps", "impact_speed_m_s"], ratio_rows)
    write_csv(res / "a2_fast_phase_space.csv", ["speed_m_s", "model", "contact", "d", "u", "s", "wall_touching"],
              phase_rows)
    plot_a2(res, ratios, paths, tails, outcome_rows, a, quick)
    return outcome_rows, ratios, paths


def classify_failure(run, tr, radius, contact=None):
    """What stopped a failed run: tunnelling (the centre passed behind the wall plane and
    left the domain below it), an escape upwards, or the engine's message."""
    msg = run.info.get("message") or run.stderr
    if len(tr) and "left the domain" in msg:
        z_last = tr[-1, Z]
        if "x = (" in msg:
            try:
                z_last = float(msg.split("x = (")[1].split(")")[0].split(",")[2])
            except (IndexError, ValueError):
                pass
        if z_last < 0:
            n = contact if contact is not None else max(len(episodes(tr[:, CONTACTS])), 1)
            return f"tunnelled: centre passed the wall plane at contact {n}"
        return "left the domain upwards"
    return "failed: " + msg.splitlines()[0] if msg else "failed"


def plot_a2(res, ratios, paths, tails, outcomes, a, quick):
    if not quick:
        fig, ax = plt.subplots(figsize=(6, 3.8))
        for m in MODELS:
            v = ratios.get(("7e4", m), [])
            if v:
                n = np.arange(1, len(v) + 1)
                inside = [(i, x) for i, x in zip(n, v) if 0.3 <= x <= 0.7]
                if inside:
                    ax.plot(*zip(*inside), ls=":", lw=0.8, ms=5, mfc="none", label=LABEL[m], **STYLE[m])
                for i, x in zip(n, v):
                    if not 0.3 <= x <= 0.7:
                        ax.annotate(f"{m}: {x:.2f}", (i, 0.69 if x > 0.7 else 0.31), fontsize=7,
                                    color=STYLE[m]["color"], ha="center")
        ax.axhline(E_REST**2, color="k", lw=0.8)
        ax.set_ylim(0.3, 0.7)
        ax.set_xlabel("bounce N")
        ax.set_ylabel("energy ratio $e^2$ at the apexes")
        notes = [f"{sp} m/s {m}: {o}" for sp, m, _, o, *_ in outcomes if o != "ok"]
        ax.text(0.99, 0.03, "\n".join(notes), transform=ax.transAxes, fontsize=6, ha="right", va="bottom")
        ax.legend(fontsize=7, loc="upper right")
        ax.set_title("A2 fast impact at 7e4 m/s (paper Fig. 5), dt = 1e-3", fontsize=10)
        fig.tight_layout()
        fig.savefig(res / "fig5_fast_energy_ratio.png", dpi=100)
        plt.close(fig)

    def rays(ax, dmax, with_f):
        dd = np.array([0, dmax])
        ax.plot(dd, dd, "k-", lw=0.7)
        ax.plot(dd, 0 * dd, "k--", lw=0.7)
        ax.plot(dd, -math.sqrt(1 - a) * dd, "k-.", lw=0.7)
        if with_f:
            ax.plot(dd, dd / E_REST, color="tab:green", ls=":", lw=0.7)

    # Fig. 6: first contact of every model at both speeds, in units of d_c
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    for ax, sp in zip(axes, ("1e5", "7e4")):
        dmax = 0.05
        for m in MODELS:
            p = paths.get((sp, m), [])
            if p:
                d, u, _ = zip(*p[0])
                dmax = max(dmax, max(d))
                ax.plot(d, u, lw=0.8, ms=4, label=LABEL[m], **STYLE[m])
            if (sp, m) in tails:  # tunnelled: the states that followed, without wall force
                d, u, _ = zip(*tails[(sp, m)])
                ax.plot(d, u, lw=0.6, ls="--", ms=4, mfc="none", **STYLE[m])
                dmax = max(dmax, max(d))
        rays(ax, 1.05 * dmax, True)
        ax.axvline(0.5, color="0.5", lw=0.6)
        ax.text(0.5, ax.get_ylim()[0], " centre on the wall plane", fontsize=6, color="0.4", va="bottom")
        ax.text(0.99, 0.99, "dashed, open: after the centre\npassed the plane (no wall force)", fontsize=6,
                transform=ax.transAxes, ha="right", va="top")
        ax.set_xlabel("d = $\\delta/d_c$")
        ax.set_title(f"first contact at {sp} m/s", fontsize=9)
    axes[0].set_ylabel("u = p + q = $-v_n\\,dt/d_c$")
    axes[0].legend(fontsize=7)
    fig.suptitle(f"A2 phase space (paper Fig. 6); lines s = 1, 0, $-\\sqrt{{1-a}}$ (a = {a:.4f}), F: s = 1/e",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(res / "fig6_fast_phase_space.png", dpi=100)
    plt.close(fig)

    # Fig. 7: every recorded contact of T, F, P at 7e4 m/s, scaled by its approach u_0
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.5), sharey=True)
    for ax, m in zip(axes, ("T", "F", "P")):
        for p in paths.get(("7e4", m), []):
            d, u, _ = zip(*p)
            u0 = u[0]
            ax.plot(np.array(d) / u0, np.array(u) / u0, lw=0.6, ms=3, color=STYLE[m]["color"],
                    marker=STYLE[m]["marker"], mfc="none")
        rays(ax, 1.6, m == "F")
        ax.set_xlim(0, 1.6)
        ax.set_ylim(-1.3, 1.3)
        ax.set_title(LABEL[m], fontsize=9)
        ax.set_xlabel("$d/u_0$")
    axes[0].set_ylabel("$u/u_0$ ($u_0$: approach at the contact step)")
    fig.suptitle("A2 at 7e4 m/s: every recorded contact (paper Fig. 7); s = 1 (solid), 0 (dashed), "
                 "$-\\sqrt{1-a}$ (dash-dot), 1/e (F, dotted)", fontsize=8)
    fig.tight_layout()
    fig.savefig(res / "fig7_phase_space_detail.png", dpi=100)
    plt.close(fig)


def case_a3(runner, res, log, quick):
    """A3 contact duration in steps (Table 2)."""
    name = "contact-duration.toml"
    rows, table = [], {}
    for conv in ("scaled", "fixed"):
        for m in MODELS:
            for dt in (1e-3, 1e-4, 1e-5):
                k, E = stiffness_at(name, dt, conv)
                r = runner.run(name, f"a3_{conv}_{m}_{dt:g}", contact_sets(m, k, E) + [f"simulation.dt={fmt(dt)}"])
                n = first_contact_steps(r.track()) if r.ok else -1
                if not r.ok:
                    log.append(f"A3 {m} dt={dt:g} ({conv}): run failed: {r.stderr}")
                table[(conv, m, dt)] = n
                rows.append([conv, m, dt, k, E, n, PAPER_TABLE2[m][(1e-3, 1e-4, 1e-5).index(dt)]])
    write_csv(res / "a3_contact_duration.csv",
              ["stiffness", "model", "dt_s", "k_n_N_m", "E_Pa", "contact_steps", "paper_steps"], rows)
    return table


def case_a4(runner, res, log, quick):
    """A4 cost: 16 spheres, dt = 1e-5, 5e6 steps (Table 1)."""
    name = "cost-16.toml"
    dt, k, E = scenario_values(name)
    rows, table = [], {}
    extra = ["simulation.duration=1.0"] if quick else []
    repeats = 1 if quick else 3  # the shortest of three runs: the machine may be shared
    for m in MODELS:
        walls = []
        for rep in range(repeats):
            r = runner.run(name, f"a4_{m}", contact_sets(m, k, E) + extra)
            info = r.info
            if not r.ok:
                log.append(f"A4 {m}: run failed: {r.stderr}")
            walls.append(info.get("wall_time_s", math.nan))
        steps = info.get("steps", 0)
        evals = info.get("contact_evaluations", 0)
        wall = min(walls)
        table[m] = (wall, evals, steps)
        p = PAPER_TABLE1[m]
        rows.append([m, steps, wall, evals, wall / evals if evals else math.nan,
                     evals / (16 * steps) if steps else math.nan, p[0], p[1], p[2], p[3]])
    write_csv(res / ("a4_cost_quick.csv" if quick else "a4_cost.csv"),
              ["model", "steps", "wall_time_s", "contact_evaluations", "wall_time_per_evaluation_s",
               "fraction_of_particle_steps_in_contact", "paper_total_s", "paper_force_s", "paper_evaluations",
               "paper_force_s_per_evaluation"], rows)
    return table


def case_a5(runner, res, log, quick):
    """A5 three spheres: relative errors of T0 and the final speed against dt (Figs. 10-11)."""
    name = "three-spheres.toml"
    if quick:
        plan = [("scaled", "P", 1e-5)]
    else:
        dts = [1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6]
        plan = [(c, m, dt) for c in ("scaled", "fixed") for m in MODELS for dt in dts]
    rows, out = [], {}
    for conv, m, dt in plan:
        k, E = stiffness_at(name, dt, conv)
        r = runner.run(name, f"a5_{conv}_{m}_{dt:g}", contact_sets(m, k, E) + [f"simulation.dt={fmt(dt)}"])
        T0, V = three_sphere_result(r.track()) if r.ok else (math.nan, math.nan)
        if not r.ok:
            log.append(f"A5 {m} dt={dt:g} ({conv}): run failed: {r.stderr}")
        eT, eV = (T0 - T0_EXACT) / T0_EXACT, (V - V_EXACT) / V_EXACT
        out[(conv, m, dt)] = (T0, V, eT, eV)
        rows.append([conv, m, dt, k, E, T0, V, eT, eV])
        shutil.rmtree(r.out, ignore_errors=True)  # the step-by-step tracks are large
    write_csv(res / ("a5_three_spheres_quick.csv" if quick else "a5_three_spheres.csv"),
              ["stiffness", "model", "dt_s", "k_n_N_m", "E_Pa", "T0_s", "final_speed_m_s", "T0_rel_error",
               "final_speed_rel_error"], rows)
    if not quick:
        for fig_name, idx, what in (("fig10_final_speed_error.png", 3, "final speed of A and B"),
                                    ("fig11_T0_error.png", 2, "separation time $T_0$")):
            fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), sharey=True)
            for ax, conv, title in ((axes[0], "scaled", "k_n, E scaled by $(10^{-3}/dt)^2$ (a fixed; paper)"),
                                    (axes[1], "fixed", "k_n, E fixed at their dt = 1e-3 values")):
                for m in MODELS:
                    pts = [(dt, abs(v[idx])) for (c, mm, dt), v in sorted(out.items())
                           if c == conv and mm == m and not math.isnan(v[idx])]
                    if pts:
                        x, y = zip(*pts)
                        ax.loglog(x, np.maximum(y, 1e-9), lw=0.8, ms=5, mfc="none", label=LABEL[m], **STYLE[m])
                ax.axhline(TOL_THREE, color="0.5", lw=0.6, ls="--")
                ax.set_xlabel("dt (s)")
                ax.set_title(title, fontsize=9)
            axes[0].set_ylabel(f"relative error of the {what}")
            axes[0].legend(fontsize=7)
            fig.suptitle(f"A5 three spheres: {what} (paper Fig. {fig_name[3:5]})", fontsize=10)
            fig.tight_layout()
            fig.savefig(res / fig_name, dpi=100)
            plt.close(fig)
    return out


# ----------------------------------------------------------------------------- main


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tsubu", nargs="?", default=os.environ.get("TSUBU", str(REPO / "build" / "tsubu")),
                    help="tsubu binary (default: $TSUBU, else build/tsubu)")
    ap.add_argument("--out", help="results folder (default: validation/results/energy-contact; "
                                  "with --quick a temporary folder)")
    ap.add_argument("--quick", action="store_true", help="reduced runs; check the spec's tolerances")
    ap.add_argument("--keep", action="store_true", help="keep the raw run folders (in OUT/runs)")
    args = ap.parse_args()
    tsubu = Path(args.tsubu).resolve()
    if not tsubu.is_file():
        print(f"error: tsubu binary not found: {tsubu} (pass it as an argument or set TSUBU)")
        return 2
    tmp = None
    if args.out:
        res = Path(args.out)
    elif args.quick:
        tmp = tempfile.mkdtemp(prefix="energy-contact-")
        res = Path(tmp)
    else:
        res = RESULTS
    res.mkdir(parents=True, exist_ok=True)
    work = res / "runs" if args.keep else Path(tempfile.mkdtemp(prefix="energy-contact-runs-"))
    work.mkdir(parents=True, exist_ok=True)
    runner = Runner(tsubu, work)
    log, failures = [], []
    t_start = time.perf_counter()
    try:
        a3 = case_a3(runner, res, log, args.quick)
        a1 = case_a1(runner, res, log)
        a5 = case_a5(runner, res, log, args.quick)
        a2 = case_a2(runner, res, log, args.quick)
        a4 = case_a4(runner, res, log, args.quick)
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    elapsed = time.perf_counter() - t_start

    # ---- report and checks (also written to OUT/summary.txt)
    report = []

    def say(line):
        print(line)
        report.append(line)

    say(f"energy-contact validation ({'quick' if args.quick else 'full'}): {runner.count} runs, "
          f"{elapsed:.1f} s; results in {res}")
    say("A3 contact duration in steps (dt = 1e-3 / 1e-4 / 1e-5; paper in brackets):")
    for conv in ("scaled", "fixed"):
        line = "  ".join(f"{m} {'/'.join(str(a3[(conv, m, dt)]) for dt in (1e-3, 1e-4, 1e-5))} "
                         f"[{'/'.join(map(str, PAPER_TABLE2[m]))}]" for m in MODELS)
        say(f"  {conv:6s}: {line}")
    for conv in ("scaled", "fixed"):
        got = [a3[(conv, "P", dt)] for dt in (1e-3, 1e-4, 1e-5)]
        if got != [P_STEPS] * 3:
            failures.append(f"A3: model P's contact lasts {'/'.join(map(str, got))} steps at dt = 1e-3/1e-4/1e-5 "
                            f"({conv} stiffness); the spec requires 3/3/3")
    say(f"A1 slow impact, energy ratio per bounce N = 1..{N_CHECK} (apex H; collision E):")
    for m in MODELS:
        b = [x for x in a1[m] if x["N"] <= N_CHECK]
        say(f"  {m}: apex " + " ".join(f"{x['ratio_apex']:.4f}" for x in b))
        say(f"     coll " + " ".join(f"{x['ratio_collision']:.4f}" for x in b))
    # The paper compares the mechanical energy "before and after the N-th collision": that is
    # what model P makes exactly e^2. At the apexes the ratio also holds the O(dt) effect of
    # symplectic Euler with gravity, about e^2 (1 - (1 + 1/e) g dt / v_in), which the model
    # does not balance; it is reported, not checked (docs/validation/energy-contact.md).
    bad = [x for x in a1["P"]
           if x["N"] <= N_CHECK and not abs(x["ratio_collision"] - E_REST**2) <= TOL_ENERGY * E_REST**2]
    if len([x for x in a1["P"] if x["N"] <= N_CHECK]) < N_CHECK:
        failures.append(f"A1: model P bounced fewer than {N_CHECK} times")
    if bad:
        worst = max(bad, key=lambda x: abs(x["ratio_collision"] - E_REST**2))
        failures.append(
            f"A1: model P's energy ratio across the collision is outside 0.49 +- 1% at bounces "
            f"{', '.join(str(x['N']) for x in bad)} (worst N = {worst['N']}: {worst['ratio_collision']:.4f}, impact "
            f"{worst['impact_speed']:.3g} m/s)")
    say("A5 three spheres, relative errors (T0, final speed):")
    for key in sorted(a5):
        conv, m, dt = key
        if args.quick or dt in (1e-3, 1e-4, 1e-5, 1e-6):
            T0, V, eT, eV = a5[key]
            say(f"  {conv:6s} {m} dt={dt:g}: T0 {T0:.6f} s ({eT:+.2e}), V {V:.6f} m/s ({eV:+.2e})")
    T0, V, eT, eV = a5[("scaled", "P", 1e-5)]
    if not (abs(eT) <= TOL_THREE and abs(eV) <= TOL_THREE):
        failures.append(f"A5: model P at dt = 1e-5: T0 = {T0:.6f} s ({eT:+.2%}), final speed {V:.6f} m/s "
                        f"({eV:+.2%}); exact {T0_EXACT:.6f} s and {V_EXACT:.6f} m/s, tolerance 0.5%")
    outcomes, ratios, _ = a2
    say("A2 fast impact (outcome, first collision energy ratio):")
    for sp, m, nb, o, r1, dmax in outcomes:
        say(f"  {sp} m/s {m}: {o}; bounces {nb}; first e2 {r1:.4f}; first contact max d {dmax:.3f}")
    say("A4 cost (wall time s, contact evaluations, steps):")
    for m in MODELS:
        w, ev, st = a4[m]
        say(f"  {m}: {w:.2f} s, {ev} evaluations, {st} steps")
    for line in log:
        say("note: " + line)
    if failures:
        say("FAILED:")
        for f in failures:
            say("  " + f)
    else:
        say("all checks passed")
    (res / "summary.txt").write_text("\n".join(report) + "\n")
    if tmp and not args.out:
        shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        return 1 if args.quick else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
