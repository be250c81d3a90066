// The sedimentation experiment end to end (docs/sedimentation.md): the reduced monodisperse
// case tests/scenarios/sediment_mono.toml runs until its deposit reaches 0.4 L, and the
// deposit and the inflow meet the checks. A validation test (about a minute).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The number after "key": in run.json (NaN when absent).
double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  return at == std::string::npos ? NAN : std::strtod(json.c_str() + at + key.size() + 4, nullptr);
}

TEST(SedimentRun, MonodisperseDepositStopsAtPoint4LWithThePapersPorosityAndCoordination) {
  const fs::path out = fs::temp_directory_path() / ("tsubu_sediment_mono_" + std::to_string(getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(TSUBU_BINARY) + " run " + TSUBU_SOURCE_DIR + "/tests/scenarios/sediment_mono.toml --out " +
                          out.string() + " > " + out.string() + ".log 2>&1";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(out.string() + ".log");
  const std::string json = slurp(out / "run.json");
  ::testing::Test::RecordProperty("wall_seconds", std::to_string(wall));
  std::printf("%s\n", json.c_str());

  // The deposit formed and the [[stop]] ended the run at 0.4 L, before the duration.
  EXPECT_NE(json.find("\"status\": \"ok\""), std::string::npos);
  EXPECT_NE(json.find("\"stop_reason\": \"deposit_height = 0.016"), std::string::npos);
  const double L = 0.04, d = 0.005, steps = json_number(json, "steps"), dt = json_number(json, "dt");
  EXPECT_NEAR(json_number(json, "deposit_height"), 0.4 * L, 1e-12);
  EXPECT_LT(steps * dt, 8.0) << "the run reached its duration";

  // Porosity of the monodisperse deposit on 0.15 L < z < 0.35 L, Monte Carlo against exact.
  const double lambda = json_number(json, "porosity"), exact = json_number(json, "porosity_exact");
  const double se = json_number(json, "porosity_standard_error");
  EXPECT_GE(lambda, 0.36);
  EXPECT_LE(lambda, 0.46);
  EXPECT_LT(se, 0.002);
  EXPECT_LE(std::abs(lambda - exact), 3 * se) << "Monte Carlo " << lambda << ", exact " << exact;

  // Coordination without rattlers (fewer than 2 contacts).
  const double z = json_number(json, "coordination_no_rattlers");
  EXPECT_GE(z, 4.0);
  EXPECT_LE(z, 6.5);

  // The inflow's mass flux, measured by the grains in the box at the end (nothing leaves it),
  // against F = rho_p phi_0 L^2 u_r.
  const double grain_mass = 2650 * M_PI / 6 * d * d * d;
  const double measured = json_number(json, "particles") * grain_mass / (steps * dt), F = json_number(json, "inflow_F");
  EXPECT_NEAR(measured / F, 1.0, 0.02) << "measured " << measured << " kg/s, F = " << F << " kg/s";
  EXPECT_NEAR(json_number(json, "inflow_F_measured"), measured, 1e-9 * measured);
  ::testing::Test::RecordProperty("porosity", std::to_string(lambda));
  ::testing::Test::RecordProperty("coordination_no_rattlers", std::to_string(z));
  ::testing::Test::RecordProperty("flux_error", std::to_string(measured / F - 1));
  if (!::testing::Test::HasFailure()) fs::remove_all(out), fs::remove(out.string() + ".log");
}

}  // namespace
