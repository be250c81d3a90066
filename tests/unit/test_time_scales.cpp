// The time scales `tsubu check` reports (sim/time_scales.hpp, docs/cli.md "Time scales and
// the time step"): contact, Rayleigh and drag relaxation times against hand calculations,
// the suggested dt, and the warning that check and run print for a dt too large to resolve
// the stiffest contact.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "tsubu/integrate/block_hermite.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/time_scales.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu;
using namespace tsubu::testing;

namespace {

// 1 mm glass beads on a simple cubic lattice above a glass floor, in a box 2 cm high.
const std::string kBeads = R"(
[simulation]
duration = 0.01
dt = 5e-6

[domain]
lower = [0, 0, 0]
upper = [0.01, 0.01, 0.02]
periodic = ["x", "y"]

[[materials]]
name = "glass"
density = 2500
youngs_modulus = 1e7
poisson = 0.3

[contact.default]
normal = "hertz_tsuji"
restitution = 0.5

[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
material = "glass"

[[particles]]
source = "lattice"
material = "glass"
lower = [0, 0, 0]
upper = [0.01, 0.01, 0.004]
diameter = 0.001
)";

TimeScales scales_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  const Scenario sc = load_scenario_text(text, "beads.toml", sets);
  return time_scales(sc, build_world(sc));
}

const std::string kValidSmall = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "valid_small.toml").string();

}  // namespace

// Worked by hand (and by a separate Python calculation: the numbers in the comments).
TEST(TimeScales, ContactAndRayleighTimesAgreeWithAHandCalculation) {
  const TimeScales ts = scales_of(kBeads);
  // Free fall over the 2 cm of the box: u = sqrt(2 g H).
  const double u = std::sqrt(2 * 9.81 * 0.02);  // 0.62642 m/s
  EXPECT_NEAR(ts.impact_speed, u, 1e-12);
  // Two equal spheres: E* = E/(2(1 - nu^2)), R* = d/4, m* = m/2, K = 4/3 E* sqrt(R*), and
  // Sota & Watanabe's Eq. 20, t = 2.94 (m*^2/(K^2 u))^(1/5).
  const double e_star = 1e7 / (2 * (1 - 0.09));
  const double m = 2500 * M_PI * 1e-9 / 6;
  const double k = 4.0 / 3.0 * e_star * std::sqrt(0.25e-3);
  const double t_pair = 2.94 * std::pow((m / 2) * (m / 2) / (k * k * u), 0.2);  // 1.0228e-4 s
  EXPECT_NEAR(t_pair, 1.0228e-4, 1e-8);
  ASSERT_EQ(ts.grains.size(), 1u);
  EXPECT_NEAR(ts.grains[0].contact_time / t_pair, 1, 1e-12);
  // The floor: m* = m, R* = d/2, a longer contact (1.1749e-4 s); the pair is the shortest.
  EXPECT_NEAR(ts.shortest_contact / t_pair, 1, 1e-12);
  // Rayleigh: pi (d/2) sqrt(rho/G)/(0.1631 nu + 0.8766), G = E/(2(1 + nu)).
  const double t_r = M_PI * 0.5e-3 * std::sqrt(2500 / (1e7 / 2.6)) / (0.1631 * 0.3 + 0.8766);  // 4.3270e-5 s
  EXPECT_NEAR(t_r, 4.3270e-5, 1e-9);
  EXPECT_NEAR(ts.grains[0].rayleigh_time / t_r, 1, 1e-12);
  // No fluid: no relaxation time; the suggestion is 1/20 of the contact, and 5e-6 s is
  // below it (20.5 steps per contact).
  EXPECT_TRUE(std::isinf(ts.shortest_relaxation));
  EXPECT_NEAR(ts.suggested_dt, t_pair / 20, 1e-18);
  EXPECT_TRUE(ts.safe);
  EXPECT_TRUE(ts.warnings.empty());
  EXPECT_EQ(ts.steps, 2000);
}

TEST(TimeScales, ATooLargeDtIsAWarningWithTheNumbers) {
  const TimeScales ts = scales_of(kBeads, {"simulation.dt=2e-5"});  // 5.1 steps per contact
  EXPECT_FALSE(ts.safe);
  ASSERT_EQ(ts.warnings.size(), 1u);
  EXPECT_NE(ts.warnings[0].find("dt = 2e-05 s cannot resolve the stiffest contact: it lasts 0.000102 s"), std::string::npos)
      << ts.warnings[0];
  EXPECT_NE(ts.warnings[0].find("only 5.11 steps"), std::string::npos) << ts.warnings[0];
  // Between 10 and 20 steps per contact: above the suggestion, no warning.
  const TimeScales near = scales_of(kBeads, {"simulation.dt=7e-6"});
  EXPECT_FALSE(near.safe);
  EXPECT_TRUE(near.warnings.empty());
}

// The relaxation time of the drag at the terminal speed: there the drag balances the net
// weight, F_D = (m - rho_f V) g, so tau = (m + C_M rho_f V)/(F_D/u_t)
// = (rho_p + rho_f/2)/(rho_p - rho_f) u_t/g.
TEST(TimeScales, FluidRelaxationTimeAgreesWithAHandCalculation) {
  const Scenario sc = load_scenario((fs::path(TSUBU_SOURCE_DIR) / "examples" / "settling" / "quartz_1mm.toml").string());
  const TimeScales ts = time_scales(sc, build_world(sc));
  ASSERT_EQ(ts.grains.size(), 1u);
  const GrainTimes& g = ts.grains[0];
  EXPECT_NEAR(g.terminal_speed, 0.15510, 1e-5);  // docs/validation/settling.md, by its own bisection
  EXPECT_NEAR(g.relaxation_time, (2650 + 500.0) / (2650 - 1000.0) * g.terminal_speed / 9.81, 1e-12);
  EXPECT_EQ(ts.shortest_relaxation, g.relaxation_time);
  // One grain and no walls: nothing to collide with, so only the fluid bounds dt.
  EXPECT_TRUE(std::isinf(ts.shortest_contact));
  EXPECT_NEAR(ts.suggested_dt, 0.1 * g.relaxation_time, 1e-15);
  EXPECT_TRUE(ts.safe);
}

// Block steps: the finest level the contact rule needs, ceil(log2(dt/(kappa_c t_c))), must
// be within simulation.block_steps.levels.
TEST(TimeScales, BlockStepsNeedALevelFineEnoughForTheStiffestContact) {
  const std::string scenario = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "block_sediment.toml").string();
  const Scenario sc = load_scenario(scenario);
  const TimeScales ts = time_scales(sc, build_world(sc));
  const int level = static_cast<int>(std::ceil(std::log2(sc.dt / (0.04 * ts.shortest_contact))));
  EXPECT_EQ(ts.needed_level, level);
  EXPECT_LE(level, sc.block_steps.levels);
  EXPECT_TRUE(ts.safe);
  EXPECT_TRUE(ts.warnings.empty());
  const Scenario coarse = load_scenario(scenario, {"simulation.block_steps.levels=3"});
  const TimeScales few = time_scales(coarse, build_world(coarse));
  EXPECT_FALSE(few.safe);
  ASSERT_EQ(few.warnings.size(), 1u);
  EXPECT_NE(few.warnings[0].find("needs level " + std::to_string(level) + ", beyond levels = 3"), std::string::npos)
      << few.warnings[0];
}

// A step rule's value so small that the finest step it asks for underflows needs a level
// beyond any: a warning, never a level taken from an undefined conversion.
TEST(TimeScales, AStepRuleThatUnderflowsIsAWarning) {
  const std::string scenario = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "block_sediment.toml").string();
  const Scenario sc = load_scenario(scenario, {"simulation.block_steps.kappa_c=1e-320"});
  const TimeScales ts = time_scales(sc, build_world(sc));
  EXPECT_EQ(ts.needed_level, kBeyondLevels);
  EXPECT_FALSE(ts.safe);
  ASSERT_EQ(ts.warnings.size(), 1u);
  EXPECT_NE(ts.warnings[0].find("no dt can resolve"), std::string::npos) << ts.warnings[0];
  EXPECT_EQ(ts.suggestion.find("-2147483648"), std::string::npos) << ts.suggestion;
}

// `tsubu check` prints the time scales, the suggestion, the steps and a timed estimate; a
// dt too large is a WARNING on stderr (the check still passes), and `tsubu run` prints it
// at its start.
TEST(TimeScales, CheckAndRunPrintTheWarning) {
  TempDir dir;
  const fs::path log = dir.path() / "log";
  ASSERT_EQ(run({"check", kValidSmall, "--set", "simulation.dt=2e-5"}, log), 0) << slurp(log);
  const std::string out = slurp(log);
  EXPECT_NE(out.find("tsubu: WARNING: dt = 2e-05 s cannot resolve the stiffest contact: it lasts 9.83e-05 s (0.001 m glass "
                     "on 0.001 m glass, hertz_tsuji (T), at 0.767 m/s), only 4.92 steps"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("glass d = 0.001001 m: contact 9.83e-05 s, Rayleigh 4.33e-05 s"), std::string::npos) << out;
  EXPECT_NE(out.find("NOT safe"), std::string::npos) << out;
  EXPECT_NE(out.find("steps: 2500"), std::string::npos) << out;
  EXPECT_NE(out.find("estimated wall time: "), std::string::npos) << out;

  ASSERT_EQ(run({"run", kValidSmall, "--out", (dir.path() / "out").string(), "--set", "simulation.dt=2e-5", "--set",
                 "simulation.duration=2e-4"},
                log),
            0)
      << slurp(log);
  EXPECT_EQ(slurp(log).rfind("tsubu: WARNING: dt = 2e-05 s cannot resolve the stiffest contact", 0), 0u) << slurp(log);

  ASSERT_EQ(run({"check", kValidSmall}, log), 0) << slurp(log);
  EXPECT_EQ(slurp(log).find("WARNING"), std::string::npos) << slurp(log);
  EXPECT_EQ(slurp(log).find("block steps pay off"), std::string::npos) << "velocity Verlet gets no integrator hint";

  // Block steps with contacts: the hint that velocity Verlet is faster where grains rest in contact.
  ASSERT_EQ(run({"check", kValidSmall, "--set", "simulation.integrator=\"block_hermite\"", "--set", "simulation.dt=1e-3"}, log), 0)
      << slurp(log);
  EXPECT_NE(slurp(log).find("block steps pay off while most grains fly free"), std::string::npos) << slurp(log);
}

// An inflow's smallest grain is its size distribution's (SizeDistribution::smallest), for
// every kind: a sieve curve of 4-10 mm grains has its shortest contact between two 4 mm
// grains, which at dt = 1e-5 s get about 6 steps of it: a warning, and a suggestion from
// them, not from the largest grains.
TEST(TimeScales, AnInflowsSmallestGrainIsItsDistributionsForASieveCurve) {
  const Scenario sc =
      load_scenario((fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "sediment_inflow.toml").string(),
                    {R"(particles.0.distribution={type="table", d=[0.004,0.006,0.01], percent_finer_by_mass=[0,30,100]})"});
  const TimeScales ts = time_scales(sc, build_world(sc));
  ASSERT_EQ(ts.grains.size(), 2u);
  EXPECT_EQ(ts.grains[0].diameter, 0.004);
  EXPECT_EQ(ts.grains[1].diameter, 0.01);
  EXPECT_TRUE(std::isfinite(ts.grains[0].contact_time) && ts.grains[0].contact_time > 0);
  EXPECT_NEAR(ts.shortest_contact / ts.grains[0].contact_time, 1, 1e-12);
  EXPECT_NE(ts.shortest_contact_what.find("0.004 m quartz on 0.004 m quartz"), std::string::npos) << ts.shortest_contact_what;
  EXPECT_NEAR(ts.suggested_dt, ts.shortest_contact / kStepsPerContact, 1e-18);
  EXPECT_FALSE(ts.safe);
  ASSERT_EQ(ts.warnings.size(), 1u);
  EXPECT_NE(ts.warnings[0].find("cannot resolve the stiffest contact"), std::string::npos) << ts.warnings[0];
}

// The wall-time estimate is a sample of the start times the run's steps; it says plainly when
// the start cannot tell the run's cost (it was 57 times low for grains settling from a loose
// cloud and 0.0015 s for an inflow run of 657 s), giving the sample's cost as a lower bound.
TEST(WallTimeEstimate, SaysWhenTheStartCannotTellTheRunsCost) {
  auto estimate = [](const std::vector<std::string>& sets) {
    const Scenario sc = load_scenario_text(kBeads, "beads.toml", sets);
    return estimate_wall_time(sc, build_world(sc), 300, 10.0);
  };
  // The lattice of touching beads on the floor, pressed together by its weight, stays packed.
  const WallTimeEstimate packed = estimate({});
  EXPECT_EQ(packed.cannot, "");
  EXPECT_GT(packed.contacts_per_grain, 1) << packed.contacts_per_grain;
  EXPECT_EQ(packed.sampled_steps, 300);
  EXPECT_NEAR(packed.run_seconds, packed.sample_seconds * 2000 / 300, 1e-12 * packed.run_seconds);
  // Grains apart under gravity, above the floor, will fall and pack.
  const WallTimeEstimate apart = estimate({"particles.0.spacing=0.0015"});
  EXPECT_LT(apart.contacts_per_grain, 1);
  EXPECT_EQ(apart.cannot.rfind("the grains start apart (", 0), 0u) << apart.cannot;
  EXPECT_NE(apart.cannot.find(" contacts a grain) and will fall and pack; a packed bed"), std::string::npos) << apart.cannot;
  // Without gravity they stay apart (a granular gas): an estimate.
  EXPECT_EQ(estimate({"particles.0.spacing=0.0015", "simulation.gravity=[0, 0, 0]"}).cannot, "");
  // An inflow brings its grains during the run.
  TempDir dir;
  const fs::path log = dir.path() / "log";
  const std::string inflow = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "inflow_small.toml").string();
  ASSERT_EQ(run({"check", inflow, "--set", "stop=[{when=\"porosity\", at_least=0.5}]"}, log), 0) << slurp(log);
  EXPECT_NE(slurp(log).find("estimated wall time: cannot estimate: the inflow brings its grains during the run, and the "
                            "cost of a step grows with them (the sample holds the 0 present at the start)\n"),
            std::string::npos)
      << slurp(log);
  // With grains at the start, the start's cost bounds the time to the duration, which a [[stop]] may cut short.
  ASSERT_EQ(run({"check", kValidSmall, "--set", "stop=[{when=\"solid_fraction\", at_least=0.5}]"}, log), 0) << slurp(log);
  EXPECT_NE(slurp(log).find("estimated wall time: cannot estimate: the grains start apart ("), std::string::npos) << slurp(log);
  EXPECT_NE(slurp(log).find(" gives at least "), std::string::npos) << slurp(log);
  EXPECT_NE(slurp(log).find(" s; to the duration: a [[stop]] may end the run sooner\n"), std::string::npos) << slurp(log);
}
