// A run whose energy grows with nothing doing work on it stops with a diagnostic.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tsubu/analysis/energy_watch.hpp"
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

namespace tsubu {
namespace {

// Issue 25, item 2: a kinetic energy that is not a finite double stops the run naming the
// particle, with the growth check on or off (it computed inf - inf and let the run go on,
// writing inf in every row).
TEST(EnergyWatch, AnEnergyThatIsNotFiniteStopsTheRunNamingTheParticle) {
  World w;
  w.particles.add(3, 0, 0.002, 2500, {0.01, 0.01, 0.01}, {0, 0, -1});
  w.particles.add(7, 0, 0.002, 2500, {0.02, 0.01, 0.01}, {});
  w.particles.omega[1] = {0, 1e160, 0};
  for (const double limit : {0.0, 0.5}) {
    EnergyWatch watch(w, Model{}, limit);
    try {
      watch.observe(w, 0);
      ADD_FAILURE() << "no error with energy_growth_limit = " << limit;
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("the kinetic energy of particle id 7 is not finite"), std::string::npos) << e.what();
    }
  }
  w.particles.omega[1] = {0, 1e150, 0};  // large, but its energy is finite
  EXPECT_NO_THROW(EnergyWatch(w, Model{}, 0.5).observe(w, 0));
}

}  // namespace
}  // namespace tsubu
