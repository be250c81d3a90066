// A run whose energy grows with nothing doing work on it stops with a diagnostic.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tsubu/app/runner.hpp"
#include "tsubu/core/error.hpp"

namespace tsubu {
namespace {

std::string run_and_report(const std::vector<std::string>& overrides) {
  const Scenario sc = load_scenario(std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/energy_growth.toml", overrides);
  const std::string out =
      ::testing::TempDir() + "tsubu_energy_" + ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::remove_all(out);
  try {
    run_scenario(sc, out, 1, false);
  } catch (const NumericalError& e) {
    return e.what();
  }
  return "";
}

TEST(EnergyWatch, UnstableTimeStepStopsTheRun) {
  const std::string why = run_and_report({});
  EXPECT_NE(why.find("the total energy grew"), std::string::npos) << why;
  EXPECT_NE(why.find("try dt/4"), std::string::npos) << why;
}

TEST(EnergyWatch, StableTimeStepRunsToTheEnd) {
  EXPECT_EQ(run_and_report({"simulation.dt=3.3e-6"}), "");  // 600 steps of an undamped oscillation
}

// Without the check the run "succeeds": the pair flies apart after two steps with 2.2 times
// its initial (elastic) energy, and its overlap never comes near the overlap limit.
TEST(EnergyWatch, ZeroLimitTurnsItOff) { EXPECT_EQ(run_and_report({"simulation.energy_growth_limit=0"}), ""); }

}  // namespace
}  // namespace tsubu

namespace tsubu {
namespace {

// The diagnostic names where the spurious energy went, not just how much there is.
TEST(EnergyWatch, TheDiagnosticNamesAParticle) {
  const std::string why = run_and_report({});
  EXPECT_NE(why.find("has the most kinetic energy"), std::string::npos) << why;
}

}  // namespace
}  // namespace tsubu
