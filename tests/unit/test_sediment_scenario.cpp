// Scenario keys of the sedimentation experiment: the inflow source (no grains at the start,
// Rubey's speed by default, `tsubu check` reports its flux) and the deposit analyses.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "scenario_run.hpp"
#include "tsubu/analysis/results.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {
namespace {

const std::string kScenario = std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/sediment_inflow.toml";

TEST(SedimentScenario, InflowSourceAndItsDefaults) {
  const Scenario sc = load_scenario(kScenario);
  const ParticleSource* src = inflow_source(sc);
  ASSERT_NE(src, nullptr);
  EXPECT_DOUBLE_EQ(src->sizes.d_min, 0.01 * std::exp(-2.0));  // spread = ln(d_max/d_min) = 2
  EXPECT_EQ(src->entry_height, 0.08);                          // z_c = 2 L
  EXPECT_EQ(src->fall_speed, rubey_speed(2650, 1000, 1e-6, 0.01, 9.81));
  EXPECT_NEAR(src->fall_speed, 0.33, 0.005);  // Rubey's speed of 1 cm quartz
  EXPECT_EQ(src->omega_star_rms, 0);
  EXPECT_EQ(build_world(sc).particles.size(), 0u) << "inflow grains arrive during the run";
  const InflowColumn c = inflow_column(sc, *src);
  EXPECT_NEAR(c.mass_flux(), 2650 * 0.1 * 0.04 * 0.04 * src->fall_speed, 1e-15);
}

TEST(SedimentScenario, CheckPrintsTheInflowRates) {
  FILE* pipe = popen((std::string(TSUBU_BINARY) + " check " + kScenario).c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[512];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  EXPECT_EQ(pclose(pipe), 0) << out;
  EXPECT_NE(out.find("  inflow_F = 0.139"), std::string::npos) << out;
  for (const char* word : {"inflow_grains_per_s = ", "inflow_phi_0 = 0.1\n", "inflow_Q = "})
    EXPECT_NE(out.find(word), std::string::npos) << out;
}

std::string slurp(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  std::string out;
  if (!f) return out;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) out.append(buf, n);
  std::fclose(f);
  return out;
}

// inflow_small.toml with a kinetic_energy analysis "ke" and the [[stop]] `stop` (TOML keys),
// its inflow stopped after 12 grains, run for at most 3 s into the folder `dir`; the run's
// exit status.
int run_twelve_grains(const std::string& dir, const std::string& stop) {
  std::string text = slurp(std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/inflow_small.toml");
  text += "\n[[analyses]]\ntype = \"kinetic_energy\"\nname = \"ke\"\n\n[[stop]]\n" + stop;
  const std::string scenario = dir + ".toml";
  std::FILE* f = std::fopen(scenario.c_str(), "w");
  if (!f) return -1;
  std::fputs(text.c_str(), f);
  std::fclose(f);
  const double grain = 2650 * M_PI / 6 * 0.004 * 0.004 * 0.004;
  // --overwrite: a folder left by an earlier run whose process had the same pid is replaced.
  const std::string cmd = std::string(TSUBU_BINARY) + " run " + scenario + " --out " + dir + " --overwrite --set simulation.duration=3" +
                          " --set particles.0.mass_limit=" + std::to_string(12.5 * grain) + " > " + dir + ".log 2>&1";
  return std::system(cmd.c_str());
}

// The "settled" stop: a mass limit of 12 grains, then [[stop]] on the kinetic energy per
// grain. The run ends ok before its duration, names the condition, and tracks an inflow id
// that never arrives without error (no rows for it).
TEST(SedimentScenario, RunStopsWhenTheGrainsHaveSettled) {
  const std::string dir = ::testing::TempDir() + "tsubu_settle_" + std::to_string(getpid());
  ASSERT_EQ(run_twelve_grains(dir, "when = \"ke_per_grain\"\nat_most = 1e-9\nafter = 0.1\n"), 0) << slurp(dir + ".log");
  const std::string json = slurp(dir + "/run.json");
  EXPECT_NE(json.find("\"status\": \"ok\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"stop_reason\": \"ke_per_grain = "), std::string::npos) << json;
  EXPECT_NE(json.find("\"particles\": 12,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"inflow_released\": 12,"), std::string::npos) << json;
  const std::string track = slurp(dir + "/track.csv");
  EXPECT_NE(track.find(",7,"), std::string::npos);
  EXPECT_EQ(track.find(",40,"), std::string::npos) << "grain 40 never enters";
  const std::string series = slurp(dir + "/series.csv");
  EXPECT_NE(series.find(",particles,inflow_mass,deposit_height,porosity,"), std::string::npos);
  EXPECT_NE(series.find(",ke,ke_per_grain,ke_speed_rms\n"), std::string::npos);
}

TEST(SedimentScenario, DepositHeightRisesWithTheRain) {
  // The surface rule on a small rain (block steps, 3.0-6 mm grains): 0 before the first
  // grains land, then rising as they do; it never falls by more than a grain's diameter below
  // what it has reached, nor jumps up by more than one.
  const std::string dir = ::testing::TempDir() + "tsubu_rain_height_" + std::to_string(getpid());
  const std::string cmd = std::string(TSUBU_BINARY) + " run " + TSUBU_SOURCE_DIR + "/tests/scenarios/rain_small.toml --out " + dir +
                          " --overwrite > " + dir + ".log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir + ".log");
  const std::string series = slurp(dir + "/series.csv");
  std::vector<std::string> columns;
  std::size_t line_end = series.find('\n'), at = 0;
  for (std::size_t comma; (comma = series.find_first_of(",", at)) < line_end; at = comma + 1) columns.push_back(series.substr(at, comma - at));
  columns.push_back(series.substr(at, line_end - at));
  const auto column = static_cast<std::size_t>(std::find(columns.begin(), columns.end(), "deposit_height") - columns.begin());
  ASSERT_LT(column, columns.size());
  std::vector<double> height;
  for (std::size_t start = line_end + 1; start < series.size(); start = series.find('\n', start) + 1) {
    std::size_t field = start;
    for (std::size_t k = 0; k < column; ++k) field = series.find(',', field) + 1;
    height.push_back(std::strtod(series.c_str() + field, nullptr));
  }
  const double d_max = 0.006;
  ASSERT_GE(height.size(), 10u);
  EXPECT_EQ(height.front(), 0.0);
  double reached = 0;
  for (std::size_t k = 1; k < height.size(); ++k) {
    EXPECT_GE(height[k], reached - d_max) << "row " << k;
    EXPECT_LE(height[k], height[k - 1] + d_max) << "row " << k;
    reached = std::max(reached, height[k]);
  }
  EXPECT_GT(height.back(), d_max);  // the deposit is more than a grain deep by t = 0.25 s
}

TEST(SedimentScenario, AtRestStopWaitsForTheInflowToEnd) {
  // The at-rest protocol (docs/sedimentation.md): a condition that holds at the start (no
  // grain moves) is not checked before the inflow has released its last grain.
  const std::string dir = ::testing::TempDir() + "tsubu_rest_" + std::to_string(getpid());
  ASSERT_EQ(run_twelve_grains(dir, "when = \"ke_speed_rms\"\nat_most = 0.003\nafter_inflow = true\n"), 0) << slurp(dir + ".log");
  const std::string json = slurp(dir + "/run.json");
  EXPECT_NE(json.find("\"stop_reason\": \"ke_speed_rms = "), std::string::npos) << json;
  EXPECT_NE(json.find("\"particles\": 12,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"inflow_waiting\": 0,"), std::string::npos) << json;
  // The rms speed is 0 at t = 0 (an empty box): without after_inflow the run would end there.
  const std::string series = slurp(dir + "/series.csv");
  EXPECT_GT(std::count(series.begin(), series.end(), '\n'), 10) << series;
}

TEST(SedimentScenario, DepositAnalysesOnASimpleCubicBed) {
  const Scenario sc = load_scenario(kScenario);
  ASSERT_EQ(sc.analyses.size(), 4u);  // one list, in the order of the file
  const AnalysisSpec& porosity = sc.analyses[1];
  EXPECT_NEAR(porosity.z_low, 0.006, 1e-15);  // 0.15 L
  EXPECT_NEAR(porosity.z_high, 0.014, 1e-15);  // 0.35 L
  EXPECT_EQ(porosity.points, 65536);
  EXPECT_NEAR(sc.analyses[3].small_diameter, 0.01 / 3, 1e-18);
  EXPECT_FALSE(sc.analyses[0].slice_rule);  // the surface rule by default, its window d_max
  EXPECT_EQ(sc.analyses[0].surface.window, 0.01);

  World w = build_world(sc);  // 10 x 10 x 5 grains of 4 mm on a simple cubic lattice, 0.001 < z < 0.021
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i)
        w.particles.add(w.particles.size(), 0, 0.004, 2650, Vec3{i + 0.5, j + 0.5, k + 0.75} * 0.004, {});
  std::map<std::string, double> r;
  for (const AnalysisSpec& a : sc.analyses)
    for (const auto& [name, value] : analysis_results(a, w)) r[name] = value;
  EXPECT_NEAR(r["porosity_exact"], 1 - M_PI / 6, 1e-12);  // the slab is two lattice periods
  EXPECT_NEAR(r["porosity"], r["porosity_exact"], 3 * r["porosity_standard_error"]);
  EXPECT_EQ(r["porosity_points"], 65536);
  EXPECT_EQ(r["porosity_grains"], 200);
  // The surface of the lattice is its top, 0.021 m, within the layering's wiggle (the window
  // of d_max = 10 mm holds 2.5 layers of 4 mm).
  EXPECT_NEAR(r["deposit_height"], 0.021, 0.001);
  EXPECT_EQ(r["gamma_upper"], 0);     // no grain below d_max/3
  EXPECT_EQ(r["coordination_no_rattlers_4"], 0);
  EXPECT_EQ(r.count("coordination_grains"), 1u);
}

// The result names (scenario/result_names.hpp, what a [[stop]] may name) and the values
// (analysis/results.hpp) are written apart: every kind gives one value for each of its names.
TEST(SedimentScenario, EveryAnalysisKindGivesAValueForEachOfItsNames) {
  const Scenario sc = load_scenario(kScenario);
  World w = build_world(sc);
  w.particles.add(0, 0, 0.004, 2650, Vec3{0.02, 0.02, 0.01}, {});
  for (const std::string text :
       {"type = 'solid_fraction'\nz_range = [0, 0.02]", "type = 'coordination'\nz_range = [0, 0.02]",
        "type = 'deposit_height'", "type = 'porosity'", "type = 'segregation'\nz_range = [0, 0.02]",
        "type = 'kinetic_energy'", "type = 'profiles'"}) {
    const AnalysisSpec a = load_analysis_text(sc, text, "test");
    std::vector<std::pair<std::string, double>> results;
    ASSERT_NO_THROW(results = analysis_results(a, w)) << text;  // std::logic_error: a count that differs
    EXPECT_EQ(results.size(), analysis_result_names(a).size()) << text;
    EXPECT_EQ(results.empty(), a.kind == AnalysisSpec::Kind::profiles) << text;
  }
}

// run.json's particle_force_evaluations with fixed steps: each evaluation's particles, so that
// a grain of an inflow counts from its entry on (it was the final count times the steps + 1,
// which for the main job's rain overstated the work 1.47 times and so understated the cost of
// a velocity Verlet step against a block-step evaluation).
TEST(SedimentScenario, ParticleForceEvaluationsCountEachGrainFromItsEntry) {
  const Scenario sc = testing::test_scenario("inflow_small.toml");
  Simulation sim = new_simulation(sc);
  std::uint64_t evaluated = sim.world().particles.size();  // the first evaluation, before the first grains enter
  sim.start();
  const int steps = 5000;  // 0.1 s: about 15 grains
  for (int s = 0; s < steps; ++s) {
    evaluated += sim.world().particles.size();  // the grains admitted at the end of the step before
    sim.step();
  }
  ASSERT_GT(sim.world().particles.size(), 5u);
  EXPECT_EQ(sim.particle_force_evaluations(), evaluated);
  EXPECT_LT(evaluated, sim.world().particles.size() * (steps + 1));
}

}  // namespace
}  // namespace tsubu
