// A numerical failure's diagnostic names its real cause: the step it happened in, the model
// whose range was left, a failure before the first step blamed on the input, not on dt.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tsubu/core/error.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu_process.hpp"
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

// A failure inside the first step is not the initial state's: it names the step under way
// (fixed steps) or the block time (block steps), and blames the step, not the input. Two
// soft grains meet at 2 m/s within the first millisecond.
TEST(Diagnostics, AFailureInsideTheFirstStepIsNotBlamedOnTheInput) {
  for (Integrator integrator : {Integrator::velocity_verlet, Integrator::block_hermite}) {
    auto [w, model] = make_world(kGlass, spec_of("hertz_tsuji", "mindlin", 0.5), 1e-3);
    w.particles.add(0, 0, 0.002, kGlass.density, {0, 0, 0}, {1, 0, 0});
    w.particles.add(1, 0, 0.002, kGlass.density, {0.0022, 0, 0}, {-1, 0, 0});
    BlockStepRules rules;
    rules.levels = 2, rules.kappa_c = 50;  // steps far too long for the contact
    Simulation sim(std::move(w), std::move(model), integrator, rules);
    const std::string why = failure_of([&] {
      sim.start();
      sim.step();
    });
    EXPECT_EQ(why.find("initial state"), std::string::npos) << why;
    if (integrator == Integrator::block_hermite) {
      EXPECT_NE(why.find("step 1, block time "), std::string::npos) << why;
      EXPECT_NE(why.find("tighten [simulation.block_steps]"), std::string::npos) << why;
    } else {
      EXPECT_NE(why.find("step 1, t = 0.001 s:"), std::string::npos) << why;
      EXPECT_NE(why.find("try dt/4"), std::string::npos) << why;
    }
  }
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
// before). The step ends after its drift, with the clock at its end and the walls moved with
// the particles: the failing state is one time (and, split among processes, every process
// ends the step there, docs/parallel.md).
TEST(Diagnostics, LeavingTheDomainNamesTheStepItHappenedIn) {
  auto [w, model] = make_world(kGlass, spec_of("hertz_tsuji", "mindlin", 0.5), 1e-3);
  w.particles.add(0, 0, 0.002, kGlass.density, {9.99, 0, 0}, {100, 0, 0});
  ForceField f(model);
  f.compute(w);
  bool evaluated = false;
  const std::string why = failure_of([&] {
    velocity_verlet_step(w, [&](double lead) { evaluated = true, testing::evaluation(f, w)(lead); });
  });
  EXPECT_NE(why.find("step 1, t = 0.001 s: particle id 0 left the domain"), std::string::npos) << why;
  EXPECT_EQ(w.step, 1);
  EXPECT_EQ(w.time, 1e-3);
  EXPECT_FALSE(evaluated);
  EXPECT_DOUBLE_EQ(w.particles.position[0].x, 10.09);
}

// Grains too soft for their impact speed overlap past the limit however small dt is: the
// failure says so when the contact lasted many steps (it said "try dt/4", and dt/4 stopped
// the same way), and `check` warns from the Hertz overlap at the impact speed (it said
// "safe"). Stiff grains with a dt too large for them keep the advice about dt.
TEST(Diagnostics, AnOverlapThePhysicsGivesIsNotBlamedOnDt) {
  using namespace tsubu::testing;
  TempDir dir;
  const std::string soft = std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/soft_impact.toml";
  const std::filesystem::path log = dir.path() / "log";
  for (const char* dt : {"simulation.dt=1e-8", "simulation.dt=2.5e-9"}) {
    ASSERT_EQ(run({"run", soft, "--out", (dir.path() / dt).string(), "--set", dt}, log), 3) << slurp(log);
    const std::string why = slurp(log);
    EXPECT_NE(why.find("so dt is not the cause (dt/4 stops the same way): the overlap is physical, the grains are too "
                       "soft for this load or impact speed; use a stiffer material (youngs_modulus) or a larger "
                       "simulation.overlap_limit"),
              std::string::npos)
        << why;
    EXPECT_EQ(why.find("try dt/4"), std::string::npos) << why;
  }
  ASSERT_EQ(run({"check", soft}, log), 0) << slurp(log);
  EXPECT_NE(slurp(log).find("tsubu: WARNING: a collision at the impact speed, 10 m/s (twice the largest initial particle "
                            "speed), presses 0.001 m soft on 0.001 m soft, hertz_tsuji (T) to an overlap of "),
            std::string::npos)
      << slurp(log);
  EXPECT_NE(slurp(log).find("beyond simulation.overlap_limit = 0.1: the run would stop whatever dt is"), std::string::npos)
      << slurp(log);
  // Stiff grains (E = 1e11 Pa: a contact of 1.5e-6 s) and a step of 3.5e-5 s that carries
  // them 0.15 diameters into each other at once: dt is the cause.
  ASSERT_EQ(run({"run", soft, "--out", (dir.path() / "stiff").string(), "--set", "materials.0.youngs_modulus=1e11", "--set",
                 "simulation.dt=3.5e-5"},
                log),
            3)
      << slurp(log);
  EXPECT_NE(slurp(log).find("try dt/4"), std::string::npos) << slurp(log);
}

}  // namespace
}  // namespace tsubu
