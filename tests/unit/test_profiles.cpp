// Profiles along z (analysis/profiles.hpp) against the slab measures they must agree with and
// hand-made velocities; D10/D50/D90 by mass; sieve-curve sampling (type = "table") against
// the table; a run writing profiles/ and run.json read back with a JSON parser.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/analysis/profiles.hpp"
#include "tsubu/source/size_moments.hpp"
#include "tsubu_process.hpp"

namespace tsubu {
namespace {

using testing::slurp;

// 4 x 4 grains of 1 mm per layer, 5 layers 1 mm apart from z = 0.5 mm, in a 4 mm periodic
// box; the top layer is of 0.5 mm grains. Velocities: (k, 0, 0) in layer k, plus +-1 in z
// alternating along x.
World layered() {
  World w;
  w.domain = {{0, 0, 0}, {0.004, 0.004, 0.01}, {true, true, false}};
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        w.particles.add(static_cast<std::int64_t>(w.particles.size()), 0, k == 4 ? 0.0005 : 0.001, 2500,
                        Vec3{i + 0.5, j + 0.5, k + 0.5} * 0.001, {double(k), 0, i % 2 ? 1.0 : -1.0});
  return w;
}

AnalysisSpec spec(int slices, double z_low, double z_high) {
  AnalysisSpec a;
  a.kind = AnalysisSpec::Kind::profiles;
  a.z_low = z_low;
  a.z_high = z_high;
  a.profile_slices = slices;
  a.class_edges = {0.0004, 0.0008, 0.0012};
  return a;
}

TEST(Profiles, SolidFractionIsTheSlabMeasureInEverySlice) {
  const World w = layered();
  for (int slices : {1, 7, 20}) {
    const AnalysisSpec a = spec(slices, 0.0002, 0.0061);
    const Profiles p = measure_profiles(a, w);
    ASSERT_EQ(p.solid_fraction.size(), static_cast<std::size_t>(slices));
    for (int k = 0; k < slices; ++k) {
      const double lo = a.z_low + (a.z_high - a.z_low) * k / slices, hi = a.z_low + (a.z_high - a.z_low) * (k + 1) / slices;
      EXPECT_NEAR(p.solid_fraction[k], solid_fraction(w, lo, hi), 1e-12) << slices << " slices, slice " << k;
      EXPECT_NEAR(p.class_fraction[0][k] + p.class_fraction[1][k], p.solid_fraction[k], 1e-15);
      EXPECT_NEAR(p.centre[k], 0.5 * (lo + hi), 1e-18);
    }
  }
}

TEST(Profiles, MeansCoordinationTemperatureAndSizesPerSlice) {
  const Profiles p = measure_profiles(spec(5, 0, 0.005), layered());  // one layer per slice
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(p.grains[k], 16);
    EXPECT_EQ(p.coordination[k], 0);  // no contacts were computed
    EXPECT_DOUBLE_EQ(p.velocity[k].x, k);
    EXPECT_DOUBLE_EQ(p.velocity[k].z, 0);
    EXPECT_DOUBLE_EQ(p.temperature[k], 1.0 / 3);  // |v - mean v|^2 = 1 for every grain
    const double d = k == 4 ? 0.0005 : 0.001;
    EXPECT_EQ(p.sizes[k].d10, d);
    EXPECT_EQ(p.sizes[k].d90, d);
    EXPECT_EQ(p.class_fraction[k == 4 ? 1 : 0][k], 0) << "the grains of slice " << k << " are in the other class";
  }
  const Profiles empty = measure_profiles(spec(2, 0.006, 0.01), layered());
  EXPECT_EQ(empty.grains[0], 0);
  EXPECT_TRUE(std::isnan(empty.velocity[0].x));
  EXPECT_TRUE(std::isnan(empty.temperature[1]));
  EXPECT_TRUE(std::isnan(empty.sizes[0].d50));
  EXPECT_EQ(empty.solid_fraction[0], 0);
}

TEST(GrainSizes, PercentilesByMass) {
  // 9 grains of 1 kg at 1 mm and one of 1 kg at 2 mm: D10 = D50 = 1 mm, D90 = 1 mm (90% of
  // the mass reached at the ninth grain), D90 = 2 mm once the large grain weighs 2 kg.
  std::vector<SizedGrain> g(9, {0.001, 1});
  g.push_back({0.002, 1});
  MassPercentiles m = mass_percentiles(g);
  EXPECT_EQ(m.d10, 0.001);
  EXPECT_EQ(m.d50, 0.001);
  EXPECT_EQ(m.d90, 0.001);
  g.back().mass = 2;
  EXPECT_EQ(mass_percentiles(g).d90, 0.002);
  EXPECT_TRUE(std::isnan(mass_percentiles({}).d50));
}

// A sieve curve: 0 % finer than 0.5 mm, 10 % than 1 mm, 60 % than 2 mm, 100 % than 4 mm.
SizeDistribution sieve_curve() {
  SizeDistribution s;
  s.kind = SizeDistribution::Kind::table;
  s.sieve = {0.0005, 0.001, 0.002, 0.004};
  s.finer = {0, 0.1, 0.6, 1};
  s.weigh_table();
  return s;
}

// The diameter at mass fraction q of the curve, log-linear between sieves.
double table_percentile(const SizeDistribution& s, double q) {
  std::size_t k = 0;
  while (s.finer[k + 1] < q) ++k;
  const double t = (q - s.finer[k]) / (s.finer[k + 1] - s.finer[k]);
  return s.sieve[k] * std::pow(s.sieve[k + 1] / s.sieve[k], t);
}

TEST(SieveCurve, SampledGrainsReproduceThePercentilesByMass) {
  const SizeDistribution s = sieve_curve();
  Random rng(5);
  std::vector<SizedGrain> grains;
  const int n = 400000;
  for (int k = 0; k < n; ++k) {
    const double d = s.sample(rng);
    ASSERT_GE(d, s.sieve.front());
    ASSERT_LE(d, s.sieve.back());
    grains.push_back({d, d * d * d});
  }
  const MassPercentiles m = mass_percentiles(grains);
  // D_q = 1 mm exactly at q = 10 %; D50 and D90 inside intervals. The mass of the sample
  // sits in ~ n * (share of large grains) grains: thousands, so the percentiles are within
  // a per cent.
  EXPECT_NEAR(m.d10, table_percentile(s, 0.1), 0.01 * table_percentile(s, 0.1));
  EXPECT_NEAR(m.d50, table_percentile(s, 0.5), 0.01 * table_percentile(s, 0.5));
  EXPECT_NEAR(m.d90, table_percentile(s, 0.9), 0.01 * table_percentile(s, 0.9));
  // The mass finer than each sieve, against the table.
  double total = 0;
  std::vector<double> finer(s.sieve.size(), 0.0);
  for (const SizedGrain& g : grains) {
    total += g.mass;
    for (std::size_t k = 0; k < s.sieve.size(); ++k)
      if (g.diameter < s.sieve[k]) finer[k] += g.mass;
  }
  for (std::size_t k = 0; k < s.sieve.size(); ++k) EXPECT_NEAR(finer[k] / total, s.finer[k], 0.005) << "sieve " << k;
  // The closed-form number moments agree with the sample (5 standard errors).
  double mean_d = 0;
  for (const SizedGrain& g : grains) mean_d += g.diameter / n;
  const double sd = std::sqrt(mean_diameter_power(s, 2) - std::pow(mean_diameter_power(s, 1), 2));
  EXPECT_NEAR(mean_d, mean_diameter_power(s, 1), 5 * sd / std::sqrt(n));
}

TEST(SieveCurve, AnEmptyIntervalGetsNoGrain) {
  SizeDistribution s = sieve_curve();
  s.finer = {0, 0.5, 0.5, 1};  // gap-graded: nothing between 1 and 2 mm
  s.weigh_table();
  Random rng(2);
  for (int k = 0; k < 100000; ++k) {
    const double d = s.sample(rng);
    ASSERT_FALSE(d > 0.001 && d < 0.002) << d;
  }
}

// The profiles run: one row per series.csv row in every profile file, headers with the
// slice centres, run.json valid JSON with the sources' grains and sizes.
TEST(ProfilesRun, WritesOneCsvPerQuantityAndRunJson) {
  testing::TempDir dir;
  const std::filesystem::path out = dir.path() / "out";
  const std::string scenario = std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/profiles_small.toml";
  ASSERT_EQ(testing::run({"run", scenario, "--out", out.string()}, dir.path() / "log"), 0) << slurp(dir.path() / "log");
  std::istringstream series(slurp(out / "series.csv"));
  std::size_t rows = 0;
  for (std::string line; std::getline(series, line);) ++rows;
  for (const char* q : {"solid_fraction", "grains", "coordination", "velocity_x", "velocity_y", "velocity_z",
                        "granular_temperature", "d10", "d50", "d90", "volume_fraction_class0", "volume_fraction_class1"}) {
    std::istringstream csv(slurp(out / "profiles" / (std::string(q) + ".csv")));
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("time [s]; ", 0), 0u) << q << ": " << header;
    EXPECT_NE(header.find(" at slice centre z [m],0.0025,0.0075,0.0125,0.0175,0.0225,0.0275"), std::string::npos) << header;
    std::size_t n = 1;
    while (std::getline(csv, line)) {
      ++n;
      EXPECT_EQ(std::count(line.begin(), line.end(), ','), 6) << q << ": " << line;
    }
    EXPECT_EQ(n, rows) << q;
  }
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "run.json"));
  EXPECT_EQ(j["status"], "ok");
  // tsubu check reports the same source sizes as run.json (no grain is lost or added).
  ASSERT_EQ(testing::run({"check", scenario}, dir.path() / "check"), 0);
  std::ostringstream expected;
  expected << std::setprecision(6) << "  particles.0: " << j["particles"].get<long>() << " grains, D10 = "
           << j["sources"][0]["d10"].get<double>() << " m, D50 = " << j["sources"][0]["d50"].get<double>() << " m, D90 = "
           << j["sources"][0]["d90"].get<double>() << " m (by mass)\n";
  EXPECT_NE(slurp(dir.path() / "check").find(expected.str()), std::string::npos) << slurp(dir.path() / "check") << expected.str();
  ASSERT_EQ(j["sources"].size(), 1u);
  const double grains = j["sources"][0]["grains"];
  EXPECT_EQ(grains, j["particles"].get<double>());
  EXPECT_GT(j["sources"][0]["d50"].get<double>(), 0.0014);  // 70 % of the mass is above 1.4 mm
  EXPECT_LT(j["sources"][0]["d10"].get<double>(), j["sources"][0]["d90"].get<double>());
  EXPECT_EQ(j["results"]["solid_fraction_grains"].get<double>(), std::stod(slurp(out / "series.csv").substr(slurp(out / "series.csv").rfind(',') + 1)));
  const std::string printed = slurp(dir.path() / "log");
  EXPECT_NE(printed.find("  solid_fraction = "), std::string::npos) << printed;
}

// An inflow whose first grain has not entered yet: its sizes are not numbers, written null;
// the results are printed in the order of the scenario, with units.
TEST(ProfilesRun, RunJsonWritesNullForASourceWithoutGrains) {
  testing::TempDir dir;
  const std::string scenario = std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/inflow_small.toml";
  const std::filesystem::path out = dir.path() / "out", log = dir.path() / "log";
  ASSERT_EQ(testing::run({"run", scenario, "--out", out.string(), "--set", "simulation.duration=0.0001"}, log), 0) << slurp(log);
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "run.json"));
  EXPECT_EQ(j["sources"][0]["grains"], 0);
  EXPECT_TRUE(j["sources"][0]["d50"].is_null()) << j["sources"];
  const std::string printed = slurp(log);
  const auto deposit = printed.find("  deposit_height = 0 m\n"), flux = printed.find("  inflow_F = "),
             porosity = printed.find("  porosity = ");
  ASSERT_NE(deposit, std::string::npos) << printed;
  EXPECT_LT(deposit, porosity);
  EXPECT_LT(porosity, flux);
  EXPECT_NE(printed.find(" kg/s\n", flux), std::string::npos) << printed;
}

// A run cut short and resumed (rows after its checkpoint, here junk, cut away) ends with
// the same profile files as an uninterrupted run.
TEST(ProfilesRun, ResumeContinuesTheProfileFiles) {
  testing::TempDir dir;
  const std::string scenario = std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/profiles_small.toml";
  const std::filesystem::path whole = dir.path() / "whole", cut = dir.path() / "cut", log = dir.path() / "log";
  const std::string every = "output.checkpoint_every_steps=400";
  ASSERT_EQ(testing::run({"run", scenario, "--out", whole.string(), "--set", every}, log), 0) << slurp(log);
  ASSERT_EQ(testing::run({"run", scenario, "--out", cut.string(), "--set", every, "--set", "simulation.duration=0.006"}, log), 0)
      << slurp(log);
  std::ofstream(cut / "profiles" / "d50.csv", std::ios::app) << "0.008,junk after the checkpoint\n";
  ASSERT_EQ(testing::run({"resume", cut.string(), "--set", "simulation.duration=0.01"}, log), 0) << slurp(log);
  for (const auto& f : std::filesystem::directory_iterator(whole / "profiles"))
    EXPECT_EQ(slurp(f.path()), slurp(cut / "profiles" / f.path().filename())) << f.path().filename();
  EXPECT_EQ(slurp(whole / "series.csv"), slurp(cut / "series.csv"));
}

}  // namespace
}  // namespace tsubu
