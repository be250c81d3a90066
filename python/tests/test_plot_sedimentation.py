"""tools/plot_sedimentation.py: the reference formulas, the Talbot statistics, and the figures
and tables drawn from a small fake set of sweep results (the script needs not the tsubu
module)."""

import csv
import json
import importlib.util
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("TSUBU_SOURCE_DIR", Path(__file__).resolve().parents[2]))
SCRIPT = ROOT / "tools" / "plot_sedimentation.py"
spec = importlib.util.spec_from_file_location("plot_sedimentation", SCRIPT)
plot = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot)

D_MAX = 0.01


def test_wu_wang_at_10_mm():
    assert plot.wu_wang_porosity(10) == pytest.approx(0.13 + 0.21 / 10.002 ** 0.21, rel=1e-12)
    assert plot.wu_wang_porosity(10) == pytest.approx(0.2594, abs=1e-4)


def test_desmond_weeks_of_one_size_and_a_spread():
    assert plot.desmond_weeks_porosity(0, 0) == pytest.approx(1 - 0.634, rel=1e-12)
    assert plot.desmond_weeks_porosity(0.2, 1.0) == pytest.approx(1 - (0.634 + 0.0658 * 0.2 + 0.0857 * 0.04), rel=1e-12)


def test_sorting_of_one_size_is_one_and_grows_with_the_spread():
    assert plot.sorting(0, 1e-9) == pytest.approx((1.0, 1.0), rel=1e-6)
    narrow, wide = plot.sorting(0, 0.6931), plot.sorting(0, 2.7726)
    assert 1 < narrow[0] < wide[0] and 1 < narrow[1] < wide[1] and narrow[1] < narrow[0]


def test_song_wang_makse_at_z_6():
    assert plot.song_wang_makse(6) == pytest.approx(6 / (6 + 2 * math.sqrt(3)), rel=1e-12)
    assert plot.song_wang_makse(6) == pytest.approx(0.634, abs=5e-4)


@pytest.mark.parametrize("spread", [0.5, 2.0])
def test_talbot_statistics_against_the_closed_forms_of_s_2(spread):
    """S = 2: the mass density is ~ d^2, so the mass median is ((d_min^3 + d_max^3)/2)^(1/3);
    the number density is ~ 1/d, so <d^k> = (d_max^k - d_min^k)/(k Sigma)."""
    d_min = D_MAX * math.exp(-spread)

    def moment(k):
        return (D_MAX ** k - d_min ** k) / (k * spread)

    mean, variance = moment(1), moment(2) - moment(1) ** 2
    skewness = (moment(3) - 3 * mean * moment(2) + 2 * mean ** 3) / variance ** 1.5
    d50, delta, s3 = plot.talbot_statistics(2, spread)
    assert d50 == pytest.approx(((d_min ** 3 + D_MAX ** 3) / 2) ** (1 / 3), rel=1e-7)
    assert delta == pytest.approx(math.sqrt(variance) / mean, rel=1e-7)
    assert s3 == pytest.approx(skewness, rel=1e-6)


def test_talbot_statistics_against_a_sample_of_s_0():
    """S = 0, Sigma = 2, drawn as tsubu draws it (inverse cumulative number distribution,
    docs/sedimentation.md): the mass median of the sample and its number statistics."""
    spread, k = 2.0, -2.0
    d_min = D_MAX * math.exp(-spread)
    u = np.random.default_rng(7).random(400_000)
    d = np.sort((d_min ** k + u * (D_MAX ** k - d_min ** k)) ** (1 / k))
    mass = np.cumsum(d ** 3)
    d50, delta, s3 = plot.talbot_statistics(0, spread)
    assert d50 == pytest.approx(d[np.searchsorted(mass, mass[-1] / 2)], rel=0.01)
    assert delta == pytest.approx(d.std() / d.mean(), rel=0.01)
    assert s3 == pytest.approx(((d - d.mean()) ** 3).mean() / d.std() ** 3, rel=0.02)


def write_results(folder, cases, exist_ok=False):
    """A results.csv as tsubu.sweep writes it (case, status, the parameters, the results) of
    cases given as (parameters, status); the results are made up, the box is L = 8 cm."""
    folder.mkdir(parents=True, exist_ok=exist_ok)
    parameters = list(cases[0][0])
    results = ["porosity", "porosity_exact", "porosity_standard_error", "porosity_grains", "coordination",
               "coordination_no_rattlers", "coordination_no_rattlers_4", "gamma_upper", "gamma_lower",
               "inflow_phi_0", "inflow_t_f"]
    with open(folder / "results.csv", "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["case", "status", "stop_reason", "wall_time_s", "steps", "particles", *parameters, *results,
                      "message"])
        for n, (values, status) in enumerate(cases):
            porosity = 0.40 + 0.01 * (n % 3)
            phi_0 = values.get("particles.0.solid_fraction", 0.1)
            result = [porosity, porosity + 0.002, 0.0019, 120, 2.5, 3.0, 4.5 if n % 4 else 0, 0.3, 0.35, phi_0,
                      math.sqrt(0.08 / 9.81)] if status == "ok" else [""] * len(results)
            out.writerow([f"case{n}", status, "", 3.5, 1000, 300, *values.values(), *result, ""])


def write_profile(case, n):
    """The profile at rest of a deposit in a box of n d_max (solid fraction 0.6 up to a surface
    at 0.65 L, 0 above) and run.json's deposit height, in the case's folder."""
    case.mkdir()
    top = 2.2 * n * D_MAX
    surface = 0.65 * n * D_MAX
    centres = np.arange(0.0005, top, 0.001)
    (case / "profiles").mkdir()
    with open(case / "profiles" / "solid_fraction.csv", "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["time [s]; solid fraction at slice centre z [m]", *centres])
        out.writerow([0.0, *([0.0] * len(centres))])
        out.writerow([1.0, *[0.6 if z < surface else 0.0 for z in centres]])
    (case / "run.json").write_text(json.dumps({"results": {"deposit_height": surface}}))


@pytest.fixture
def sweeps(tmp_path):
    """Fake results of the sweeps (fig5-6 with a failed and a pending case, fig8 with its
    series, box and finite-size with their profiles); the box of fig5-6 and vacuum only
    through inflow_t_f."""
    root = tmp_path / "sweeps"

    def one_size(phi, seed, law="total"):
        return {"contact.default.friction_bound": law, "particles.0.solid_fraction": phi, "simulation.seed": seed}

    grid = [(one_size(phi, seed, law), "ok") for law in ("total", "spring") for phi in (0.3, 0.1, 0.03, 0.01)
            for seed in (1, 2, 3)]
    write_results(root / "fig5-6", grid[:-2] + [(one_size(0.01, 2, "spring"), "failed"),
                                                (one_size(0.01, 3, "spring"), "pending")])
    write_results(root / "fig5-6-stop", grid)
    write_results(root / "vacuum", [(one_size(phi, seed, law), "ok") for law in ("total", "spring")
                                    for phi in (0.1, 0.03, 0.01) for seed in (1, 2, 3)])
    write_results(root / "finite-size", [({"simulation.seed": seed, "domain.upper": f"[{n * D_MAX}, {n * D_MAX}, 0.3]"},
                                           "ok") for seed in (1, 2, 3) for n in (4, 8, 16)])
    for k, n in enumerate(n for seed in (1, 2, 3) for n in (4, 8, 16)):
        write_profile(root / "finite-size" / f"case{k}", n)
    for sweep in ("fig7-rest", "fig7-stop"):
        write_results(root / sweep, [({"contact.default.friction_bound": law, "particles.0.distribution.exponent": s,
                                       "particles.0.solid_fraction": 0.1, "particles.0.distribution.spread": spread}, "ok")
                                      for law in ("total", "spring") for s in (0, 1, 2) for spread in (0.5, 1.0, 2.0)])
    write_results(root / "fig8", [({"particles.0.solid_fraction": phi}, "ok") for phi in (0.1, 0.01)])
    write_results(root / "fig5-6-hindered", [({"particles.0.solid_fraction": phi, "simulation.seed": seed}, "ok")
                                             for phi in (0.3, 0.1) for seed in (1, 2, 3)])
    write_results(root / "rcp-mono", [({"simulation.seed": seed}, "ok") for seed in (1, 2, 3)])
    for sweep in ("fig7-hindered", "rcp"):
        write_results(root / sweep, [({"particles.0.distribution.exponent": s, "particles.0.solid_fraction": 0.1,
                                       "particles.0.distribution.spread": spread}, "ok")
                                      for s in (0, 1, 2) for spread in (0.5, 1.0, 2.0)])
    # The box: L = 4 and 8 cm, seeds 1 and 2, each with its profile at rest.
    write_results(root / "box", [({"simulation.seed": seed, "domain.upper": f"[{n * D_MAX}, {n * D_MAX}, {2.2 * n * D_MAX}]"},
                                   "ok") for n in (4, 8) for seed in (1, 2)])
    for k, n in enumerate((4, 4, 8, 8)):
        write_profile(root / "box" / f"case{k}", n)
    for n in range(2):
        case = root / "fig8" / f"case{n}"
        case.mkdir()
        with open(case / "series.csv", "w", newline="") as f:
            out = csv.writer(f)
            out.writerow(["time", "deposit_height", "slice_height", "gamma_upper", "gamma_upper_grains", "gamma_lower",
                          "gamma_lower_grains"])
            for t in np.linspace(0, 1, 11):
                grains = 0 if t < 0.3 else 10
                out.writerow([t, 0.04 * 0.4 * t, 0.004 * round(4 * t), 0.3 if grains else 0, grains,
                              0.2 + 0.1 * t if grains else 0, grains])
    return root


def run(*args, previous=None):
    """The script on the fake sweeps; --previous: the given CSV, else none (the report's own
    sedimentation.csv would fill in the sweeps a test leaves out)."""
    previous = previous or Path(args[args.index("--sweeps") + 1]).parent / "no-previous.csv"
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args), "--previous", str(previous)], check=True,
                          capture_output=True, text=True).stdout


def test_the_script_draws_every_figure_and_the_table(sweeps, tmp_path):
    out = tmp_path / "out"
    printed = run("--sweeps", sweeps, "--out", out)
    for name in ("phi-z", "flux", "finite-size", "fig7", "box", "fig8", "hindered"):
        assert (out / f"sedimentation-{name}.png").stat().st_size > 10_000, printed
    with open(out / "sedimentation.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 24 + 24 + 18 + 9 + 18 + 18 + 4 + 2 + 6 + 9 + 3 + 9
    box = [r for r in rows if r["sweep"] == "box"]
    assert {(r["L_over_d"], r["S"], r["Sigma"], r["law"]) for r in box} == {("4", "0", "2.0794", "bounded"),
                                                                            ("8", "0", "2.0794", "bounded")}
    assert "sweep fig5-6: 22 of 24 cases ok" in printed
    failed = next(r for r in rows if r["status"] == "failed")
    assert failed["porosity"] == "" and failed["Q_over_Q0"] == "0.1"
    first = rows[0]
    assert (first["sweep"], first["Q_over_Q0"], first["L_over_d"], first["fluid"]) == ("fig5-6", "3", "8", "yes")
    assert first["coordination_no_rattlers_4"] == ""  # the run's 0: no grain with 4 contacts
    assert first["law"] == "bounded" and first["protocol"] == "at rest"
    assert {r["protocol"] for r in rows if r["sweep"] in ("fig5-6-stop", "fig7-stop")} == {"paper's stop"}
    assert {r["protocol"] for r in rows if r["sweep"] not in ("fig5-6-stop", "fig7-stop")} == {"at rest"}
    sizes = [(r["L_over_d"], r["porosity_clear"]) for r in rows if r["sweep"] == "finite-size"]
    # The slab kept 2 d clear of floor and surface: none in the deposit 2.6 d deep at L = 4 d.
    assert [(size, round(float(p), 12) if p else None) for size, p in sizes[:3]] == [("4", None), ("8", 0.4), ("16", 0.4)]
    vacuum = [r for r in rows if r["sweep"] == "vacuum"]
    assert {r["fluid"] for r in vacuum} == {"no"} and vacuum[0]["S"] == ""
    fig8 = [r for r in rows if r["sweep"] == "fig8"]
    assert [(r["S"], r["Sigma"], r["law"]) for r in fig8] == [("0", "2.0794", "bounded")] * 2
    assert {r["variant"] for r in rows if r["sweep"] in ("fig5-6-hindered", "fig7-hindered")} == {"hindered"}
    assert {r["variant"] for r in rows if r["sweep"] in ("rcp-mono", "rcp")} == {"frictionless"}
    assert {r["variant"] for r in rows if r["sweep"] == "fig7-rest"} == {""}
    assert {r["law"] for r in rows if r["sweep"] == "fig7-rest"} == {"bounded", "as printed"}


def test_missing_sweeps_are_skipped_and_said(sweeps, tmp_path):
    for sweep in ("fig5-6", "vacuum", "fig7-rest"):
        (sweeps / sweep / "results.csv").unlink()
    out = tmp_path / "out"
    printed = run("--sweeps", sweeps, "--out", out)
    assert "sedimentation-phi-z.png: not drawn" in printed
    assert "sedimentation-fig7.png: not drawn" in printed
    assert "sweep vacuum: no " in printed
    assert sorted(p.name for p in out.glob("*.png")) == ["sedimentation-box.png", "sedimentation-fig8.png",
                                                           "sedimentation-finite-size.png", "sedimentation-hindered.png"]


def test_markdown_tables(sweeps, tmp_path):
    printed = run("--sweeps", sweeps, "--out", tmp_path / "out", "--markdown")
    assert not (tmp_path / "out").exists()
    assert "| fluid | variant | friction law | protocol | L/d | Q/Q0 | seeds | porosity |" in printed
    assert "| no | – | bounded | at rest | 8 | 0.1 | 3 |" in printed
    assert "| yes | – | as printed | paper's stop | 8 | 3 | 3 |" in printed
    assert "| yes | – | bounded | at rest | 16 | 1 | 3 |" in printed
    assert "| yes | hindered | bounded | at rest | 8 | 3 | 3 |" in printed
    assert "| yes | frictionless | – | at rest | 8 | 1 | 3 |" in printed
    assert "porosity, 2 d clear |" in printed and "| 0.400 ± 0.000 |" in printed
    assert "| fig7-hindered | bounded | 1 | 0 | 2 | 1 |" in printed
    assert "| fig7-rest | bounded | 1 | 0 | 2 | 1 |" in printed
    d50, delta, skewness = plot.talbot_statistics(0, 2.0)
    geometric, trask = plot.sorting(0, 2.0)
    assert f"| 0 | 2 | 1.35 | {d50 * 1e3:.2f} | {geometric:.2f} | {trask:.2f} | {delta:.3f} | {skewness:.2f} |" in printed
    # The box: at L = 4 cm the deposit (2.6 cm) is too thin for a slab 2 cm clear of floor and
    # surface; at 8 cm the slab 2-3.2 cm has the profile's solid fraction 0.6.
    assert "| 4 | 2 | " in printed and "none (too thin), none (too thin)" in printed
    assert "| 2.0-3.2, 2.0-3.2 | 0.400 ± 0.000 |" in printed
    assert "No finished case" not in printed


def test_sweeps_not_found_are_read_from_the_previous_csv(sweeps, tmp_path):
    """A sweep run on another machine stays in the report: its rows of the previous
    sedimentation.csv stand in for it, with the same figures and tables."""
    first = tmp_path / "first"
    run("--sweeps", sweeps, "--out", first)
    for sweep in ("fig7-rest", "fig7-stop", "fig5-6"):
        (sweeps / sweep / "results.csv").unlink()
    second = tmp_path / "second"
    printed = run("--sweeps", sweeps, "--out", second, previous=first / "sedimentation.csv")
    assert f"sweep fig7-rest: 18 of 18 cases ok, from {first / 'sedimentation.csv'}" in printed
    assert (second / "sedimentation-fig7.png").stat().st_size > 10_000
    assert (first / "sedimentation.csv").read_text() == (second / "sedimentation.csv").read_text()
    # A sweep re-run in part here: its finished cases are this run's, the others the previous rows.
    write_results(sweeps / "fig7-rest", [({"contact.default.friction_bound": "total", "particles.0.distribution.exponent": 0,
                                           "particles.0.solid_fraction": 0.1, "particles.0.distribution.spread": 0.5},
                                          "ok")] + [({"contact.default.friction_bound": "total"}, "pending")] * 17,
                  exist_ok=True)
    results = sweeps / "fig7-rest" / "results.csv"
    results.write_text(results.read_text().replace(",0.4,0.402,", ",0.3,0.302,", 1))  # this run's porosity
    third = tmp_path / "third"
    printed = run("--sweeps", sweeps, "--out", third, previous=first / "sedimentation.csv")
    assert "sweep fig7-rest: 18 of 18 cases ok" in printed
    with open(third / "sedimentation.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["sweep"] == "fig7-rest"]
    with open(first / "sedimentation.csv", newline="") as f:
        before = [r for r in csv.DictReader(f) if r["sweep"] == "fig7-rest"]
    assert rows[1:] == before[1:] and (rows[0]["porosity"], before[0]["porosity"]) == ("0.3", "0.4")
