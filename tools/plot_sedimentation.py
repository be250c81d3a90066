#!/usr/bin/env -S /usr/bin/python3
"""Figures and tables of the sedimentation report (docs/validation/sedimentation.md).

    plot_sedimentation.py [--sweeps DIR] [--previous CSV] [--out DIR] [--markdown]

Reads DIR/<sweep>/results.csv (default DIR: out/sweeps of the repository) of the sweeps of
examples/sedimentation/sweeps/ (fig5-6 (one size at rest), fig5-6-stop (the same by the
paper's protocol), vacuum, finite-size, fig7-rest (the mixtures at rest), box, fig7-stop (the
same by the paper's protocol), fig8, and the variants fig5-6-hindered, fig7-hindered with
hindered settling, rcp-mono and rcp without friction), the series.csv of each fig8 case and
the profiles of each box and finite-size case; only cases with status ok enter the figures.
A sweep not found in DIR is read from the rows of --previous (default: the report's own
sedimentation.csv), so that runs made on other machines stay in the report; its figures that
need a run's folder (fig8's series, the profiles) are then not drawn for it. Writes into
--out (default: docs/validation of the repository):

    sedimentation-phi-z.png        solid fraction against Z without rattlers at rest (Fig. 5),
                                   a panel per friction law, water and vacuum
    sedimentation-flux.png         porosity against the flux Q/Q_0 (Fig. 6), a panel per
                                   friction law: water and vacuum at rest, water by the
                                   paper's protocol
    sedimentation-finite-size.png  porosity (0.15-0.35 L and the slab kept 2 d clear of floor
                                   and surface) and Z against the box size L/d, at rest
    sedimentation-fig7.png         porosity of Talbot mixtures against their spread (Fig. 7),
                                   a panel per friction law at Q_0, at rest and by the paper's
                                   protocol, with the frictionless deposits and Desmond & Weeks
    sedimentation-fig7-flux.png    porosity of the mixtures at rest against the flux Q/Q_0,
                                   a panel per friction law, a line per spread and S
    sedimentation-fig8.png         segregation Gamma of the two layers against time (Fig. 8)
    sedimentation-hindered.png     porosity with and without hindered settling
    sedimentation-box.png          the mixture S = 0, Sigma = 2.08 at rest in boxes of 4 and
                                   8 d_max (box): solid fraction against height, and the
                                   porosity of the 0.15-0.35 L slab and of the slab kept
                                   2 d_max clear of the floor and of the surface
    sedimentation.csv              one row per case of every sweep present

A missing sweep is skipped and a figure without data is not drawn; both are said on stdout.
With --markdown the script writes nothing and prints the report's tables to stdout instead.

Values are means over the seeds of a case; error bars are the standard error of that mean
(standard deviation over the seeds / sqrt(seeds)); a case of one seed has none (the Monte
Carlo error of one deposit understates the scatter between deposits several times).

Needs Debian's /usr/bin/python3 with python3-numpy and python3-matplotlib (not the tsubu
module).
"""
import argparse
import csv
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SWEEPS = ("fig5-6", "fig5-6-stop", "vacuum", "finite-size", "fig7-rest", "fig7-stop", "box", "fig8",
          "fig5-6-hindered", "fig7-hindered", "rcp-mono", "rcp")
WITHOUT_FLUID = {"vacuum"}
MIXTURES = {"fig7-rest", "fig7-stop", "box", "fig8", "fig7-hindered", "rcp"}
AT_THE_STOP = {"fig5-6-stop", "fig7-stop"}  # the paper's protocol; every other sweep measures at rest
PROTOCOLS = {True: "paper's stop", False: "at rest"}
PROFILED = {"box", "finite-size"}  # sweeps whose slab kept clear of floor and surface is read from the profiles
# What a sweep sets for all its cases ([set], not a parameter of its results.csv).
SWEEP_CONSTANTS = {"box": {"S": 0.0, "Sigma": 2.0794, "law": "bounded"}, "fig8": {"S": 0.0, "Sigma": 2.0794, "law": "bounded"},
                   "finite-size": {"law": "bounded"}, "fig5-6-hindered": {"law": "bounded"},
                   "fig7-hindered": {"law": "bounded"}}
LAWS = {"total": "bounded", "spring": "as printed"}  # contact.default.friction_bound
VARIANTS = {"fig5-6-hindered": "hindered", "fig7-hindered": "hindered", "rcp-mono": "frictionless",
            "rcp": "frictionless"}  # the others: the paper's model
TALBOT_PARAMETERS = {"S": "particles.0.distribution.exponent", "Sigma": "particles.0.distribution.spread"}
POLY_EXAMPLE = {"S": 0.0, "Sigma": 2.0}  # poly.toml's Talbot exponent and spread
D_MAX = 0.01        # m: the diameter of the one-size sweeps, d_max of the mixtures
GRAVITY = 9.81      # m/s^2, the examples' gravity
PHI_0_OF_Q_0 = 0.1  # inflow solid fraction of the paper's highest flux Q_0
RANDOM_LOOSE, RANDOM_CLOSE = 0.55, 0.64  # solid fractions of random packings of one size
RESULTS = ("porosity", "porosity_exact", "porosity_standard_error", "porosity_grains", "coordination",
           "coordination_no_rattlers", "coordination_no_rattlers_4", "gamma_upper", "gamma_lower",
           "wall_time_s", "particles")
CLEAR_SLAB = ("clear_low", "clear_high", "porosity_clear")
CSV_COLUMNS = ("sweep", "case", "status", "protocol", "phi_0", "Q_over_Q0", "S", "Sigma", "L_over_d", "seed",
               "fluid", "variant", "law", *RESULTS, *CLEAR_SLAB)


def wu_wang_porosity(d50_mm):
    """Porosity of a deposit of median grain size d50 (mm) by Wu & Wang (2006)."""
    return 0.13 + 0.21 / (d50_mm + 0.002) ** 0.21


def desmond_weeks_porosity(delta, skewness):
    """Porosity of the frictionless random close packing of spheres whose radii have
    polydispersity delta (standard deviation over mean) and skewness, by Desmond & Weeks
    (2014): phi_RCP = 0.634 + 0.0658 delta + 0.0857 S delta^2 (fitted for delta <= 0.4)."""
    return 1 - (0.634 + 0.0658 * delta + 0.0857 * skewness * delta ** 2)


def sorting(exponent, spread):
    """(geometric sorting sqrt(d84/d16), Trask's sqrt(d75/d25)), by mass, of a Talbot mixture."""
    q = {f: mass_quantile(exponent, spread, f) for f in (0.16, 0.25, 0.75, 0.84)}
    return math.sqrt(q[0.84] / q[0.16]), math.sqrt(q[0.75] / q[0.25])


def song_wang_makse(z):
    """Solid fraction of a jammed packing with mean coordination z (rattlers left out), by
    Song, Wang & Makse (2008)."""
    return z / (z + 2 * math.sqrt(3))


def talbot_moments(exponent, spread, d_max=D_MAX, points=20001):
    """(d, mass finer than d (fraction), [number moments <d^0> ... <d^3>, unnormalised]) of a
    Talbot distribution: the number density of diameters is n(d) ~ d^(exponent - 3) on
    [d_min, d_max], d_min = d_max exp(-spread), so the mass density is ~ d^exponent.
    Integrated by the trapezoidal rule in ln d on `points` points."""
    log_d = np.linspace(math.log(d_max) - spread, math.log(d_max), points)
    d = np.exp(log_d)
    number = d ** (exponent - 2)  # n(d) dd = d^(exponent - 3) d dln(d)

    def cumulative(f):
        return np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(log_d))])

    mass = cumulative(number * d ** 3)
    return d, mass / mass[-1], [cumulative(number * d ** k)[-1] for k in range(4)]


def mass_quantile(exponent, spread, fraction):
    """The diameter below which `fraction` of a Talbot distribution's mass lies (d50: 0.5)."""
    d, finer, _ = talbot_moments(exponent, spread)
    return float(np.interp(fraction, finer, d))


def talbot_statistics(exponent, spread):
    """(d50 by mass, polydispersity, skewness) of a Talbot distribution: d50 is the diameter
    below which half of the mass lies; the polydispersity delta is the standard deviation
    of the diameter over its mean and the skewness the third standardised moment, both of
    the number distribution."""
    d50 = mass_quantile(exponent, spread, 0.5)
    _, _, moments = talbot_moments(exponent, spread)
    mean = moments[1] / moments[0]
    variance = moments[2] / moments[0] - mean ** 2
    third = moments[3] / moments[0] - 3 * mean * moments[2] / moments[0] + 2 * mean ** 3
    return d50, math.sqrt(variance) / mean, third / variance ** 1.5


def number(text):
    """A cell of a results.csv as a float, NaN when empty."""
    return float(text) if text else math.nan


def box_size(row):
    """L (m): the first number of the domain.upper parameter, else from the free-fall time
    t_f = sqrt(L/g) that the run reports."""
    if row.get("domain.upper"):
        return float(row["domain.upper"].strip("[]").split(",")[0])
    return GRAVITY * number(row.get("inflow_t_f", "")) ** 2


def without_empty(z, least):
    """A mean coordination over the grains with at least `least` contacts, NaN when no grain
    was left (a run reports 0 then)."""
    return z if z >= least else math.nan


def case_from_row(folder, sweep, row):
    """A case of a results.csv by the physics' names, with its output folder; its results
    only when its status is ok."""
    ok = row["status"] == "ok"
    phi_0 = number(row.get("particles.0.solid_fraction") or row.get("inflow_phi_0", ""))
    case = {"sweep": sweep, "case": row["case"], "folder": Path(folder) / sweep / row["case"],
            "status": row["status"], "phi_0": phi_0,
            "Q_over_Q0": round(phi_0 / PHI_0_OF_Q_0, 6), "S": math.nan, "Sigma": math.nan,
            "L_over_d": round(box_size(row) / D_MAX, 2),
            "seed": int(row.get("simulation.seed") or 1),  # 1: the examples' seed
            "fluid": "no" if sweep in WITHOUT_FLUID else "yes", "variant": VARIANTS.get(sweep, ""),
            "law": LAWS.get(row.get("contact.default.friction_bound", ""), ""), "protocol": PROTOCOLS[sweep in AT_THE_STOP]}
    if sweep in MIXTURES:
        for name, key in TALBOT_PARAMETERS.items():
            case[name] = number(row[key]) if key in row else POLY_EXAMPLE[name]
    case.update(SWEEP_CONSTANTS.get(sweep, {}))
    # The second slab of the box and finite-size sweeps, read once from the deposit's profile at rest.
    case["clear_low"], case["clear_high"], case["porosity_clear"] = (
        clear_slab(case["folder"]) if sweep in PROFILED and ok else (math.nan, math.nan, math.nan))
    for key in RESULTS:
        case[key] = number(row.get(key, "")) if ok else math.nan
    case["coordination_no_rattlers"] = without_empty(case["coordination_no_rattlers"], 2)
    case["coordination_no_rattlers_4"] = without_empty(case["coordination_no_rattlers_4"], 4)
    return case


def case_from_csv(row):
    """A case of sedimentation.csv (a row written by write_csv), without an output folder."""
    case = {key: number(row.get(key, "")) for key in (*RESULTS, *CLEAR_SLAB, "phi_0", "Q_over_Q0", "S", "Sigma",
                                                       "L_over_d")}
    case.update({key: row[key] for key in ("sweep", "case", "status", "fluid", "variant", "law")})
    case.update(folder=None, seed=int(row["seed"]),
                protocol=row.get("protocol") or PROTOCOLS[row["sweep"] in AT_THE_STOP])
    return case


def read_sweeps(folder, previous=None):
    """{sweep: [case, ...]} in SWEEPS order: the sweeps whose results.csv exists under folder,
    and for the others the rows of the previous sedimentation.csv (if given and present). In a
    sweep found under folder, a case that has not finished there (pending, failed,
    interrupted) keeps the previous row of the same case if that one finished."""
    found, earlier = {}, {}
    if previous and Path(previous).exists():
        with open(previous, newline="") as f:
            for row in csv.DictReader(f):
                earlier.setdefault(row["sweep"], {})[row["case"]] = case_from_csv(row)
    for sweep in SWEEPS:
        path = Path(folder) / sweep / "results.csv"
        before = earlier.get(sweep, {})
        if path.exists():
            with open(path, newline="") as f:
                cases = [case_from_row(folder, sweep, row) for row in csv.DictReader(f)]
            found[sweep] = [c if c["status"] == "ok" or before.get(c["case"], c)["status"] != "ok" else before[c["case"]]
                            for c in cases]
        elif before:
            found[sweep] = list(before.values())
    return found


def finished(sweeps, name):
    """The cases of a sweep with status ok ([] for a sweep not found)."""
    return [c for c in sweeps.get(name, []) if c["status"] == "ok"]


def by(cases, *keys):
    """The cases grouped by the values of keys, in sorted order: [(values, [case, ...])]."""
    groups = {}
    for c in cases:
        groups.setdefault(tuple(c[k] for k in keys), []).append(c)
    return sorted(groups.items(), key=lambda item: item[0])


def over_seeds(cases, key):
    """(mean, error) of a quantity over the cases of one group (its seeds): the error is the
    standard error of the mean, the standard deviation over them / sqrt(seeds); NaN for a
    single case (one deposit tells nothing of the scatter between deposits)."""
    known = [c for c in cases if not math.isnan(c[key])]
    if not known:
        return math.nan, math.nan
    if len(known) == 1:
        return known[0][key], math.nan
    values = np.array([c[key] for c in known])
    return float(values.mean()), float(values.std(ddof=1) / math.sqrt(len(values)))


def bars(errors):
    """Error bars for errorbar(): None where there are none (NaN: one seed), else 0 for the NaNs."""
    values = np.atleast_1d(np.asarray(errors, dtype=float))
    if np.isnan(values).all():
        return None
    return np.nan_to_num(values) if np.ndim(errors) else float(np.nan_to_num(values)[0])


FLUX_STYLES = {3.0: ("C3", "v"), 1.0: ("C0", "o"), 0.5: ("C4", "D"), 0.3: ("C1", "s"), 0.1: ("C2", "^")}


def flux_style(q):
    """(colour, marker) of a flux Q/Q_0."""
    return FLUX_STYLES.get(q, ("0.4", "o"))


def box_label(cases):
    """'L/d = 4, 8' of the boxes of the cases, for a title."""
    return "L/d = " + ", ".join(f"{b:g}" for b in sorted({c["L_over_d"] for c in cases}))


def law_panels(cases, width=5.5, height=4.5):
    """(figure, [(law, axes)]): a panel per friction law of the cases, bounded first."""
    laws = sorted({c["law"] for c in cases}, key=lambda law: (law != "bounded", law))
    fig, axes = plt.subplots(1, len(laws), figsize=(width * len(laws) + 1, height), sharey=True,
                             layout="constrained", squeeze=False)
    return fig, list(zip(laws, axes[0]))


def finish_law_panels(fig, panels, png, ylabel, title, legend="small"):
    """law_panels' titles, grids, the first panel's y label and legend; writes png."""
    for law, ax in panels:
        ax.set_title(f"friction law {law}", fontsize="medium")
        ax.grid(alpha=0.3)
    panels[0][1].set_ylabel(ylabel)
    panels[0][1].legend(fontsize=legend)
    save(fig, png, title + "; error bars: standard error of the mean over the seeds")


def plot_phi_z(sweeps, png):
    """Fig. 5 at rest: solid fraction against Z without rattlers (< 4 contacts), a panel per
    friction law, water and vacuum, with the frictionless deposits, the Song-Wang-Makse line
    and the random loose and close packings of one size. False without data."""
    water, vacuum = finished(sweeps, "fig5-6"), finished(sweeps, "vacuum")
    if not water + vacuum:
        return False
    fig, panels = law_panels(water + vacuum)
    for law, ax in panels:
        for cases, medium in ((water, "water"), (vacuum, "vacuum")):
            for (q,), group in by([c for c in cases if c["law"] == law], "Q_over_Q0"):
                z, z_error = over_seeds(group, "coordination_no_rattlers_4")
                porosity, porosity_error = over_seeds(group, "porosity")
                colour, marker = flux_style(q)
                ax.errorbar(z, 1 - porosity, xerr=bars(z_error), yerr=bars(porosity_error),
                            color=colour, capsize=3,
                            marker="*" if medium == "vacuum" else marker, ms=12 if medium == "vacuum" else 7,
                            ls="none", label=f"{medium}, Q/Q0 = {q:g}")
        frictionless = finished(sweeps, "rcp-mono")
        if frictionless:
            z, z_error = over_seeds(frictionless, "coordination_no_rattlers_4")
            porosity, porosity_error = over_seeds(frictionless, "porosity")
            ax.errorbar(z, 1 - porosity, xerr=bars(z_error), yerr=bars(porosity_error), color="k", marker="P", ms=9,
                        ls="none", capsize=3, label="water, no friction, Q/Q0 = 1")
        z = np.linspace(3.5, 6.5, 50)
        ax.plot(z, song_wang_makse(z), "k-", lw=1, label="Song, Wang & Makse: φ = Z/(Z + 2√3)")
        ax.axhline(RANDOM_LOOSE, color="0.5", ls="--", lw=1, label=f"random loose packing {RANDOM_LOOSE}")
        ax.axhline(RANDOM_CLOSE, color="0.5", ls=":", lw=1, label=f"random close packing {RANDOM_CLOSE}")
        ax.set_xlabel("Z without rattlers (fewer than 4 contacts left out)")
    finish_law_panels(fig, panels, png, "solid fraction φ = 1 - porosity",
                      f"One size, d = 1 cm, {box_label(water + vacuum)}, at rest", legend="x-small")
    return True


def save(fig, png, title=None):
    """Writes the figure (with a title over all its panels, if given) and closes it."""
    if title:
        fig.suptitle(title, fontsize="medium")
    fig.savefig(png, dpi=110)
    plt.close(fig)


def plot_flux(sweeps, png):
    """Fig. 6: porosity against the flux, a panel per friction law: water and vacuum at rest,
    water by the paper's protocol (dashed), and Wu & Wang at d50 = d. False without data."""
    water, stop, vacuum = finished(sweeps, "fig5-6"), finished(sweeps, "fig5-6-stop"), finished(sweeps, "vacuum")
    if not water + vacuum:
        return False
    fig, panels = law_panels(water + vacuum)
    d50_mm = D_MAX * 1e3
    predicted = wu_wang_porosity(d50_mm)
    fluxes = sorted({c["Q_over_Q0"] for c in water + vacuum})
    for law, ax in panels:
        for cases, label, style, size in ((water, "water, at rest", "o-", 7), (vacuum, "vacuum, at rest", "*-", 12),
                                          (stop, "water, paper's protocol", "x--", 7)):
            points = [(q, *over_seeds(group, "porosity"))
                      for (q,), group in by([c for c in cases if c["law"] == law], "Q_over_Q0")]
            if points:
                q, porosity, error = zip(*points)
                ax.errorbar(q, porosity, yerr=bars(error), fmt=style, ms=size, capsize=3, label=label)
        ax.axhline(predicted, color="k", ls=":", lw=1, label=f"Wu & Wang, d50 = {d50_mm:g} mm: {predicted:.3f}")
        ax.set_xscale("log")
        ax.set_xticks(fluxes, [f"{q:g}" for q in fluxes])
        ax.minorticks_off()
        ax.set_xlabel("flux Q/Q0 (= φ0/0.1)")
    finish_law_panels(fig, panels, png, "porosity of 0.15 L < z < 0.35 L", f"One size, d = 1 cm, {box_label(water + vacuum)}")
    return True


def plot_finite_size(sweeps, png):
    """Porosity (the 0.15-0.35 L slab, and the slab kept 2 d clear of floor and surface) and Z
    (both rattler definitions) against the box size L/d, at rest. False without data."""
    cases = finished(sweeps, "finite-size")
    if not cases:
        return False
    groups = by(cases, "L_over_d")
    sizes = [size for (size,), _ in groups]
    fig, (ax_porosity, ax_z) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    for key, label, marker in (("porosity", "0.15 L < z < 0.35 L", "o"), ("porosity_clear", "2 d clear", "s")):
        points = [(size, *over_seeds(g, key)) for (size,), g in groups if not math.isnan(over_seeds(g, key)[0])]
        if points:
            size, mean, error = zip(*points)
            ax_porosity.errorbar(size, mean, yerr=bars(error), marker=marker, capsize=3, label=label)
    ax_porosity.set_ylabel("porosity at rest")
    ax_porosity.legend(fontsize="small")
    for key, label in (("coordination_no_rattlers", "fewer than 2 contacts left out"),
                       ("coordination_no_rattlers_4", "fewer than 4 contacts left out")):
        z = [over_seeds(g, key) for _, g in groups]
        ax_z.errorbar(sizes, *zip(*z), marker="o", capsize=3, label=label)
    ax_z.set_ylabel("Z without rattlers")
    ax_z.legend(fontsize="small")
    for ax in (ax_porosity, ax_z):
        ax.set_xscale("log", base=2)
        ax.set_xticks(sizes, [f"{s:g}" for s in sizes])
        ax.minorticks_off()
        ax.set_xlabel("box size L/d")
        ax.grid(alpha=0.3)
    q = sorted({c["Q_over_Q0"] for c in cases})
    save(fig, png, f"One size, d = 1 cm, in water at Q/Q0 = {', '.join(f'{v:g}' for v in q)}, bounded law, at rest; "
                   "error bars: standard error of the mean over the seeds")
    return True


def fig7_cases(sweeps, protocol="rest"):
    """The finished mixtures of Fig. 7 at rest (fig7-rest) or by the paper's protocol (fig7-stop)."""
    return finished(sweeps, f"fig7-{protocol}")


def plot_fig7(sweeps, png):
    """Fig. 7: porosity of the mixtures against Sigma at rest, a panel per friction law and flux,
    a line per S; dashed, the same runs measured by the paper's protocol; dotted, Wu & Wang for
    each mixture's d50 by mass; dash-dot, the frictionless deposits at rest; grey, Desmond &
    Weeks' random close packing of S = 0. False without data."""
    cases = [c for c in fig7_cases(sweeps) if c["Q_over_Q0"] == 1]
    if not cases:
        return False
    stop = fig7_cases(sweeps, "stop")
    panels = by(cases, "law", "Q_over_Q0")
    fig, axes = plt.subplots(1, len(panels), figsize=(4.5 * len(panels) + 1, 4.8), sharey=True,
                             layout="constrained", squeeze=False)
    for ax, ((law, q), panel) in zip(axes[0], panels):
        spreads = sorted({c["Sigma"] for c in panel})
        for n, ((exponent,), line) in enumerate(by(panel, "S")):
            points = [(spread, *over_seeds(g, "porosity")) for (spread,), g in by(line, "Sigma")]
            spread, porosity, error = zip(*points)
            ax.errorbar(spread, porosity, yerr=bars(error), marker="o", capsize=3, color=f"C{n}", label=f"S = {exponent:g}, at rest")
            paper = [(sp, over_seeds(g, "porosity")[0]) for (sp,), g in
                     by([c for c in stop if (c["law"], c["Q_over_Q0"], c["S"]) == (law, q, exponent)], "Sigma")]
            if paper:
                ax.plot(*zip(*paper), "--", marker="x", color=f"C{n}", label=f"S = {exponent:g}, paper's protocol")
            predicted = [wu_wang_porosity(talbot_statistics(exponent, s)[0] * 1e3) for s in spread]
            ax.plot(spread, predicted, ":", color=f"C{n}", label=f"Wu & Wang, S = {exponent:g}")
            close = [(spread, over_seeds(g, "porosity")[0])
                     for (spread,), g in by([c for c in finished(sweeps, "rcp") if c["S"] == exponent], "Sigma")]
            if close:
                ax.plot(*zip(*close), "-.", color=f"C{n}", lw=1, label=f"no friction, S = {exponent:g}")
        ax.plot(spreads, [desmond_weeks_porosity(*talbot_statistics(0, s)[1:]) for s in spreads], "-", color="0.6",
                lw=2, alpha=0.6, label="Desmond & Weeks RCP, S = 0")
        ax.set_title(f"friction law {law}, Q/Q0 = {q:g}", fontsize="medium")
        ax.set_xlabel("spread Σ = ln(d_max/d_min)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("porosity of 0.15 L < z < 0.35 L")
    axes[0][0].legend(fontsize="x-small")
    save(fig, png, f"Talbot mixtures, d_max = 1 cm, {box_label(cases)}, at rest; "
                   "error bars: standard error of the mean over the seeds")
    return True


def plot_fig7_flux(sweeps, png):
    """The mixtures at rest against the flux: porosity against Q/Q_0, a panel per friction
    law, a colour per spread Sigma and a marker per S (lines only where a mixture has more
    than one flux). False without a mixture at two fluxes."""
    cases = fig7_cases(sweeps)
    mixtures = [g for _, g in by(cases, "law", "Sigma", "S") if len({c["Q_over_Q0"] for c in g}) > 1]
    if not mixtures:
        return False
    laws = sorted({g[0]["law"] for g in mixtures})
    spreads = sorted({g[0]["Sigma"] for g in mixtures})
    fig, axes = plt.subplots(1, len(laws), figsize=(5 * len(laws) + 1, 4.8), sharey=True, layout="constrained",
                             squeeze=False)
    for ax, law in zip(axes[0], laws):
        for g in (g for g in mixtures if g[0]["law"] == law):
            spread, exponent = g[0]["Sigma"], g[0]["S"]
            points = [(q, *over_seeds(h, "porosity")) for (q,), h in by(g, "Q_over_Q0")]
            q, porosity, error = zip(*points)
            ax.errorbar(q, porosity, yerr=bars(error), marker="osD"[int(exponent) % 3], capsize=3,
                        color=f"C{spreads.index(spread)}", label=f"Σ = {spread:.2f}, S = {exponent:g}")
        ax.set_xscale("log")
        ax.set_title(f"friction law {law}", fontsize="medium")
        ax.set_xlabel("flux Q/Q0")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="x-small")
    axes[0][0].set_ylabel("porosity of 0.15 L < z < 0.35 L, at rest")
    save(fig, png, f"Talbot mixtures at rest against the flux, d_max = 1 cm, {box_label(cases)}; "
                   "error bars: standard error of the mean over the seeds")
    return True


def plot_hindered(sweeps, png):
    """Porosity with and without hindered settling: one size against the flux (left), the
    mixtures at Q_0 against Sigma (right). False without hindered data."""
    one_size, mixtures = finished(sweeps, "fig5-6-hindered"), finished(sweeps, "fig7-hindered")
    if not one_size + mixtures:
        return False
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    fluxes = sorted({c["Q_over_Q0"] for c in one_size})
    plain_one_size = [c for c in finished(sweeps, "fig5-6") if c["law"] == "bounded"]
    for cases, label, style in ((plain_one_size, "paper's fluid", "o-"), (one_size, "hindered settling", "s--")):
        points = [(q, *over_seeds(g, "porosity"))
                  for (q,), g in by(cases, "Q_over_Q0") if q in fluxes]
        if points:
            q, porosity, error = zip(*points)
            left.errorbar(q, porosity, yerr=bars(error), fmt=style, color="k", capsize=3, label=label)
    left.set_xscale("log")
    left.set_xticks(fluxes, [f"{q:g}" for q in fluxes])
    left.minorticks_off()
    left.set_xlabel("flux Q/Q0")
    left.set_ylabel("porosity of 0.15 L < z < 0.35 L")
    left.set_title(f"One size, d = 1 cm, {box_label(one_size or plain_one_size)}, bounded law", fontsize="medium")
    plain = [c for c in fig7_cases(sweeps) if c["Q_over_Q0"] == 1 and c["law"] == "bounded"]
    for cases, label, style in ((plain, "paper's fluid", "o-"), (mixtures, "hindered", "s--")):
        for n, ((exponent,), line) in enumerate(by(cases, "S")):
            points = [(spread, *over_seeds(g, "porosity")) for (spread,), g in by(line, "Sigma")]
            spread, porosity, error = zip(*points)
            right.errorbar(spread, porosity, yerr=bars(error), fmt=style, color=f"C{n}", capsize=3,
                           label=f"S = {exponent:g}, {label}")
    right.set_xlabel("spread Σ = ln(d_max/d_min)")
    right.set_title(f"Talbot mixtures at Q/Q0 = 1, {box_label(mixtures or plain)}", fontsize="medium")
    for ax in (left, right):
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
    save(fig, png, "Hindered settling (Richardson-Zaki) against the paper's fluid, at rest; "
                   "error bars: standard error of the mean over the seeds")
    return True


def read_series(path):
    """series.csv as {column: array}."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: np.array([number(r[key]) for r in rows]) for key in rows[0]} if rows else {}


def plot_fig8(sweeps, png):
    """Fig. 8: Gamma of the upper and lower layers against time, a panel per flux. False without data."""
    cases = [c for c in finished(sweeps, "fig8") if c["folder"]]
    if not cases:
        return False
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases) + 1, 4.5), sharey=True,
                             layout="constrained", squeeze=False)
    for ax, case in zip(axes[0], sorted(cases, key=lambda c: -c["Q_over_Q0"])):
        series = read_series(case["folder"] / "series.csv")
        box = case["L_over_d"] * D_MAX
        # A layer counts once the deposit covers it (deposit height, in slices of 0.1 L, at
        # least the slice through the layer's middle); before, the grains falling through it
        # make Γ jump between 0 and 1 (drawn faint).
        for layer, heights, style, covered in (("upper", "0.25-0.35 L", "-", 0.3), ("lower", "0.15-0.25 L", "--", 0.2)):
            gamma = series[f"gamma_{layer}"]
            grains = series.get(f"gamma_{layer}_grains")
            shown = grains > 0 if grains is not None else np.isfinite(gamma)  # Γ is 0 in an empty layer
            deposit = series["deposit_height"] >= (covered - 0.01) * box
            ax.plot(series["time"][shown], gamma[shown], "k" + style, alpha=0.25, lw=0.8)
            ax.plot(series["time"][shown & deposit], gamma[shown & deposit], "k" + style,
                    label=f"{layer} layer ({heights}), deposit over it")
        stopped = series["time"][series["slice_height"] >= 0.4 * box - 1e-9] if "slice_height" in series else []
        if len(stopped):
            ax.axvline(stopped[0], color="C3", ls=":", lw=1, label="the paper's stop (slice rule at 0.4 L)")
        ax.set_title(f"Q/Q0 = {case['Q_over_Q0']:g}", fontsize="medium")
        ax.set_xlabel("time (s)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("Γ: share of d < d_max/3 in the solid volume")
    axes[0][0].legend(fontsize="small")
    save(fig, png, f"Talbot S = {cases[0]['S']:g}, Σ = {cases[0]['Sigma']:g}, d_max = 1 cm, {box_label(cases)}")
    return True


CLEAR = 2 * D_MAX  # m: the box sweep's second slab keeps this clear of the floor and of the surface


def last_profile(folder, quantity="solid_fraction"):
    """(slice centres (m), values) of the last row of a profiles file: the deposit at rest."""
    with open(Path(folder) / "profiles" / f"{quantity}.csv", newline="") as f:
        rows = list(csv.reader(f))
    return np.array([float(x) for x in rows[0][1:]]), np.array([number(x) for x in rows[-1][1:]])


def clear_slab(folder):
    """(z_low, z_high, porosity) of the slab CLEAR above the floor and below the deposit's
    surface (run.json's deposit_height at rest) of the run in `folder`, from the whole slices
    of the profile at rest (exact sphere-slab volumes); porosity NaN when the deposit is too
    thin for one."""
    z, phi = last_profile(folder)
    surface = json.loads((Path(folder) / "run.json").read_text())["results"]["deposit_height"]
    half = 0.5 * (z[1] - z[0])
    inside = (z - half >= CLEAR - 1e-12) & (z + half <= surface - CLEAR + 1e-12)
    if not inside.any():
        return CLEAR, surface - CLEAR, math.nan
    return float(z[inside][0] - half), float(z[inside][-1] + half), 1 - float(phi[inside].mean())


def plot_box(sweeps, png):
    """The mixture in boxes of 4 and 8 d_max: solid fraction against height at rest (each
    seed), with the two slabs, and their porosities against the box. False without data."""
    cases = [c for c in finished(sweeps, "box") if c["folder"]]
    if not cases:
        return False
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    colours = {4.0: "C0", 8.0: "C3"}
    top = 0.0  # m, the highest slice with grains
    for c in sorted(cases, key=lambda c: (c["L_over_d"], c["seed"])):
        z, phi = last_profile(c["folder"])
        top = max(top, float(z[phi > 0.01].max()))
        colour = colours.get(c["L_over_d"], "0.4")
        left.plot(z / D_MAX, phi, color=colour, alpha=0.8, lw=1,
                  label=f"L = {c['L_over_d']:g} d_max" if c["seed"] == 1 else None)
        box = c["L_over_d"] * D_MAX
        left.axvspan(0.15 * box / D_MAX, 0.35 * box / D_MAX, color=colour, alpha=0.08)
        if c["clear_high"] > c["clear_low"]:
            left.axvspan(c["clear_low"] / D_MAX, c["clear_high"] / D_MAX, color=colour, alpha=0.15, hatch="//", fill=False)
    left.set_xlim(0, top / D_MAX + 1)
    left.set_xlabel("height z / d_max")
    left.set_ylabel("solid fraction (1 mm slices, at rest)")
    left.set_title("shaded: the 0.15-0.35 L slab; hatched: 2 d_max clear of floor and surface", fontsize="small")
    left.grid(alpha=0.3)
    left.legend(fontsize="small")
    for k, (label, key) in enumerate((("0.15-0.35 L", "porosity_exact"), ("2 d_max clear", "porosity_clear"))):
        for n, ((size,), group) in enumerate(by(cases, "L_over_d")):
            mean, error = over_seeds(group, key)
            if not math.isnan(mean):
                right.errorbar(size + 0.15 * (k - 0.5), mean, yerr=bars(error), fmt="os"[k], color=f"C{k + 1}",
                               capsize=3, label=label if n == 0 else None)
    right.set_xlabel("box L / d_max")
    right.set_ylabel("porosity at rest (mean ± standard error over seeds)")
    right.set_xticks(sorted({c["L_over_d"] for c in cases}))
    right.grid(alpha=0.3)
    right.legend(fontsize="small")
    save(fig, png, "Talbot S = 0, Σ = 2.08, Q_0, bounded friction law, at rest")
    return True


def csv_value(value):
    """A value as sedimentation.csv writes it: empty for NaN, whole numbers without '.0'."""
    if isinstance(value, float):
        return "" if math.isnan(value) else int(value) if value.is_integer() else value
    return value


def write_csv(sweeps, path):
    """sedimentation.csv: one row per case of every sweep found, CSV_COLUMNS."""
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(CSV_COLUMNS)
        for cases in sweeps.values():
            for c in cases:
                out.writerow([csv_value(c[k]) for k in CSV_COLUMNS])


def cell(mean, error=math.nan, digits=3):
    """mean ± error as text; '–' for a missing value."""
    if math.isnan(mean):
        return "–"
    return f"{mean:.{digits}f}" + ("" if math.isnan(error) else f" ± {error:.{digits}f}")


def table(header, rows):
    """The lines of a Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


COLUMNS = {  # column: (heading, digits)
    "porosity": ("porosity", 3), "porosity_exact": ("exact", 3), "porosity_grains": ("grains in slab", 0),
    "coordination": ("Z", 2), "coordination_no_rattlers": ("Z (< 2 out)", 2),
    "coordination_no_rattlers_4": ("Z (< 4 out)", 2), "gamma_upper": ("Γ upper", 3),
    "gamma_lower": ("Γ lower", 3), "wall_time_s": ("wall time (s)", 0),
    "porosity_clear": ("porosity, 2 d clear", 3),
}
WITH_ERRORS = {"porosity", "porosity_clear"}  # and the coordinations


def deposit_cells(group, keys):
    """The table cells of the columns over a group of seeds: the porosity and Z as mean ±
    standard error of the mean (none for one seed), the others as means."""
    cells = []
    for key in keys:
        if key in WITH_ERRORS or key.startswith("coordination"):
            mean, error = over_seeds(group, key)
        else:
            mean, error = over_seeds(group, key)[0], math.nan
        cells.append(cell(mean, error, COLUMNS[key][1]))
    return cells


ONE_SIZE = ("porosity", "porosity_exact", "porosity_grains", "coordination", "coordination_no_rattlers",
            "coordination_no_rattlers_4", "wall_time_s")
MIXTURE = ("porosity", "porosity_exact", "porosity_grains", "coordination", "coordination_no_rattlers_4", "gamma_upper",
           "gamma_lower", "wall_time_s")


def markdown(sweeps):
    """The report's tables (Markdown), one per sweep present, then the mixtures' statistics."""
    lines = []
    one_size = (("Figs. 5-6, one size", ONE_SIZE, finished(sweeps, "fig5-6") + finished(sweeps, "fig5-6-stop")
                 + finished(sweeps, "vacuum") + finished(sweeps, "fig5-6-hindered") + finished(sweeps, "rcp-mono")),
                ("Finite size, one size", (*ONE_SIZE, "porosity_clear"), finished(sweeps, "finite-size")))
    for title, columns, cases in one_size:
        if cases:
            rows = [[fluid, variant or "–", law or "–", protocol, f"{size:g}", f"{q:g}", str(len(g)),
                     *deposit_cells(g, columns)]
                    for (fluid, variant, law, protocol, size, q), g in
                    by(cases, "fluid", "variant", "law", "protocol", "L_over_d", "Q_over_Q0")]
            lines += [f"{title} (±: the standard error of the mean over the seeds):", "",
                      *table(["fluid", "variant", "friction law", "protocol", "L/d", "Q/Q0", "seeds",
                              *(COLUMNS[k][0] for k in columns)], rows), ""]
    mixtures = (fig7_cases(sweeps) + fig7_cases(sweeps, "stop") + finished(sweeps, "fig8") + finished(sweeps, "fig7-hindered")
                + finished(sweeps, "rcp"))
    if mixtures:
        rows = [[sweep, law or "–", f"{q:g}", f"{exponent:g}", f"{spread:g}", str(len(g)), *deposit_cells(g, MIXTURE)]
                for (sweep, law, q, exponent, spread), g in by(mixtures, "sweep", "law", "Q_over_Q0", "S", "Sigma")]
        lines += ["Figs. 7-8, Talbot mixtures (±: the standard error of the mean over the seeds, none for one seed;"
                  " fig7-rest and rcp at rest, fig7-stop at the paper's stop):", "",
                  *table(["sweep", "friction law", "Q/Q0", "S", "Σ", "seeds", *(COLUMNS[k][0] for k in MIXTURE)], rows), ""]
        rows = []
        close = finished(sweeps, "rcp")
        for exponent, spread in sorted({(c["S"], c["Sigma"]) for c in mixtures if c["sweep"] != "rcp"}):
            d50, delta, skewness = talbot_statistics(exponent, spread)
            geometric, trask = sorting(exponent, spread)
            rcp = over_seeds([c for c in close if (c["S"], c["Sigma"]) == (exponent, spread)], "porosity")[0]
            rows.append([f"{exponent:g}", f"{spread:g}", f"{D_MAX * math.exp(-spread) * 1e3:.2f}", f"{d50 * 1e3:.2f}",
                         f"{geometric:.2f}", f"{trask:.2f}", f"{delta:.3f}", f"{skewness:.2f}",
                         f"{wu_wang_porosity(d50 * 1e3):.3f}", f"{desmond_weeks_porosity(delta, skewness):.3f}", cell(rcp)])
        lines += ["The mixtures (d_max = 10 mm; d50 and the sorting by mass, σ_g = √(d84/d16) and Trask's √(d75/d25);"
                  " δ and skewness of the number distribution; Desmond & Weeks' random close packing, fitted for"
                  " δ ≤ 0.4; the porosity of the frictionless deposit at rest, rcp.toml):", "",
                  *table(["S", "Σ", "d_min (mm)", "d50 (mm)", "σ_g", "Trask", "δ", "skewness", "Wu & Wang porosity",
                          "Desmond & Weeks RCP porosity", "frictionless deposit porosity"], rows), ""]
    boxes = finished(sweeps, "box")
    if boxes:
        rows = []
        for (size,), g in by(boxes, "L_over_d"):
            mean, error = over_seeds(g, "porosity_clear")
            span = ", ".join(f"{c['clear_low'] / D_MAX:.1f}-{c['clear_high'] / D_MAX:.1f}"
                             if c["clear_high"] > c["clear_low"] else "none (too thin)" for c in g)
            rows.append([f"{size:g}", str(len(g)), *deposit_cells(g, ("porosity", "porosity_grains", "coordination")),
                         span, cell(mean, error), *deposit_cells(g, ("wall_time_s",))])
        lines += ["The box (S = 0, Σ = 2.08, Q_0, bounded law, at rest; ±: standard error over the seeds):", "",
                  *table(["L/d_max", "seeds", "porosity 0.15-0.35 L", "grains in slab", "Z",
                          "clear slab (d_max, per seed)", "porosity, clear slab", "wall time (s)"], rows), ""]
    lines += [f"No finished case of sweep `{sweep}` yet." for sweep in SWEEPS
              if not finished(sweeps, sweep)]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sweeps", type=Path, default=ROOT / "out" / "sweeps", help="folder of the sweeps' outputs")
    parser.add_argument("--previous", type=Path, default=ROOT / "docs" / "validation" / "sedimentation.csv",
                        help="sedimentation.csv whose rows stand in for the sweeps not found under --sweeps")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "validation", help="folder to write into")
    parser.add_argument("--markdown", action="store_true", help="print the report's tables, write nothing")
    args = parser.parse_args()
    sweeps = read_sweeps(args.sweeps, args.previous)
    if args.markdown:
        print(markdown(sweeps))
        return
    for sweep in SWEEPS:
        if sweep in sweeps:
            source = f", from {args.previous}" if sweeps[sweep] and not sweeps[sweep][0]["folder"] else ""
            print(f"sweep {sweep}: {len(finished(sweeps, sweep))} of {len(sweeps[sweep])} cases ok{source}")
        else:
            print(f"sweep {sweep}: no {args.sweeps / sweep / 'results.csv'}, skipped")
    args.out.mkdir(parents=True, exist_ok=True)
    figures = (("sedimentation-phi-z.png", plot_phi_z, "fig5-6 or vacuum"),
               ("sedimentation-flux.png", plot_flux, "fig5-6 or vacuum"),
               ("sedimentation-finite-size.png", plot_finite_size, "finite-size"),
               ("sedimentation-fig7.png", plot_fig7, "fig7-rest"),
               ("sedimentation-fig7-flux.png", plot_fig7_flux, "fig7-rest at two fluxes"),
               ("sedimentation-box.png", plot_box, "box"),
               ("sedimentation-fig8.png", plot_fig8, "fig8"),
               ("sedimentation-hindered.png", plot_hindered, "fig5-6-hindered or fig7-hindered"))
    for name, draw, needs in figures:
        if draw(sweeps, args.out / name):
            print(args.out / name)
        else:
            print(f"{name}: not drawn, no finished case of {needs}")
    if sweeps:
        write_csv(sweeps, args.out / "sedimentation.csv")
        print(args.out / "sedimentation.csv")
    else:
        print("sedimentation.csv: not written, no sweep found")


if __name__ == "__main__":
    main()
