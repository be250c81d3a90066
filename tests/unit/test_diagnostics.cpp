// A numerical failure's diagnostic names its real cause: the step it happened in, the model
// whose range was left, a failure before the first step blamed on the input, not on dt.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tsubu/core/error.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

using testing::make_world;
using testing::spec_of;

const Material kGlass{"glass", 2500, 1e7, 0.3};

std::string failure_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const NumericalError& e) {
    return e.what();
  }
  return "no failure";
}

TEST(Diagnostics, AFailureBeforeTheFirstStepBlamesTheInputNotDt) {
  auto [w, model] = make_world(kGlass, spec_of("hertz_tsuji", "mindlin", 0.5), 1e-6);
  w.particles.add(0, 0, 0.002, kGlass.density, {0, 0, 0}, {});
  w.particles.add(1, 0, 0.002, kGlass.density, {0.001, 0, 0}, {});  // half a diameter deep
  ForceField f(model);
  const std::string why = failure_of([&] { f.compute(w); });
  EXPECT_NE(why.find("step 0,"), std::string::npos) << why;
  EXPECT_NE(why.find("the initial state, before any time step"), std::string::npos) << why;
  EXPECT_EQ(why.find("dt/4"), std::string::npos) << why;
}

// energy_conserving_2005's range is named only when that model made the force non-finite.
TEST(Diagnostics, ANonFiniteForceNamesEnergyConserving2005OnlyWhenInUse) {
  auto [w, model] = make_world(kGlass, spec_of("hertz_tsuji", "mindlin", 0.5), 1e-6);
  w.particles.add(0, 0, 0.002, kGlass.density, {0, 0, 0}, {std::nan(""), 0, 0});
  w.particles.add(1, 0, 0.002, kGlass.density, {0.00199, 0, 0}, {});
  w.step = 7;
  ForceField f(model);
  const std::string why = failure_of([&] { f.compute(w); });
  EXPECT_NE(why.find("(a non-finite force)"), std::string::npos) << why;
  EXPECT_NE(why.find("hertz_tsuji"), std::string::npos) << why;
  EXPECT_EQ(why.find("energy_conserving_2005"), std::string::npos) << why;
}

// The drift that carries a particle out belongs to the step under way (it named the one
// before).
TEST(Diagnostics, LeavingTheDomainNamesTheStepItHappenedIn) {
  auto [w, model] = make_world(kGlass, spec_of("hertz_tsuji", "mindlin", 0.5), 1e-3);
  w.particles.add(0, 0, 0.002, kGlass.density, {9.99, 0, 0}, {100, 0, 0});
  ForceField f(model);
  f.compute(w);
  const std::string why = failure_of([&] { velocity_verlet_step(w, f); });
  EXPECT_NE(why.find("step 1, t = 0.001 s: particle id 0 left the domain"), std::string::npos) << why;
}

}  // namespace
}  // namespace tsubu
