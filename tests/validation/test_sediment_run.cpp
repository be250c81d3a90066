// The sedimentation experiment end to end (docs/sedimentation.md): the reduced monodisperse
// case tests/scenarios/sediment_mono.toml runs until its deposit is at rest, and the deposit
// is a packing of one size: porosity between random close and loose packing, every grain
// held. A validation test (about a minute).
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

TEST(SedimentRun, MonodisperseDepositAtRestIsAPackingOfOneSize) {
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

  // The inflow ended (293 grains) and the [[stop]] found the deposit at rest before the
  // duration; its surface is about 0.5 L high, above the slab's 0.35 L by more than a grain.
  EXPECT_NE(json.find("\"status\": \"ok\""), std::string::npos);
  EXPECT_NE(json.find("\"stop_reason\": \"ke_speed_rms = "), std::string::npos) << json;
  EXPECT_EQ(json_number(json, "particles"), 293);
  const double L = 0.04, d = 0.005, height = json_number(json, "deposit_height");
  EXPECT_GT(height, 0.35 * L + d);
  EXPECT_LT(height, 0.65 * L);

  // Porosity of the deposit at rest on 0.15 L < z < 0.35 L: between random close packing
  // (0.36) and random loose packing in water (0.45, Jerkins et al.), Monte Carlo against exact.
  const double lambda = json_number(json, "porosity"), exact = json_number(json, "porosity_exact");
  const double se = json_number(json, "porosity_standard_error");
  EXPECT_GE(lambda, 0.36);
  EXPECT_LE(lambda, 0.45);
  EXPECT_LT(se, 0.002);
  EXPECT_LE(std::abs(lambda - exact), 3 * se) << "Monte Carlo " << lambda << ", exact " << exact;

  // At rest every grain is held: the mean coordination with every grain counted is at
  // least 3.5 (a still-forming deposit measured by the paper's protocol reads 1-3).
  const double z = json_number(json, "coordination");
  EXPECT_GE(z, 3.5);
  EXPECT_LE(z, 6.5);
  ::testing::Test::RecordProperty("porosity", std::to_string(lambda));
  ::testing::Test::RecordProperty("coordination", std::to_string(z));
  if (!::testing::Test::HasFailure()) fs::remove_all(out), fs::remove(out.string() + ".log");
}

}  // namespace
