// Whole-engine tests on scenario files: a settled bed's packing, and thread-count agreement.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "scenario_run.hpp"

namespace tsubu {
namespace {

World run(const std::string& name, int threads, const std::vector<std::string>& overrides = {}) {
  return testing::run_test_scenario(name, overrides, threads);
}

// A poured monodisperse bed with friction 0.5 packs between random loose (0.55) and random
// close (0.64) packing, with 4 to 6 contacts per non-rattler, away from the floor and the
// loose top (4 diameters from each).
TEST(SettledBed, MonodisperseSolidFractionBetweenLooseAndClosePacking) {
  const World w = run("settle_mono.toml", 1);
  const double d = 0.002;
  double top = 0;
  for (const Vec3& x : w.particles.position) top = std::max(top, x.z);
  ASSERT_GT(top, 12 * d) << "the bed should be deep enough to measure";
  const double phi = solid_fraction(w, 4 * d, top - 4 * d);
  const double z = coordination(w, 4 * d, top - 4 * d, true);
  EXPECT_GE(phi, 0.55);
  EXPECT_LE(phi, 0.64);
  EXPECT_GE(z, 4.0);
  EXPECT_LE(z, 6.0);
  ::testing::Test::RecordProperty("solid_fraction", std::to_string(phi));
  ::testing::Test::RecordProperty("coordination_no_rattlers", std::to_string(z));
}

using testing::same_bits;

// The force sums are accumulated serially in contact order, so 1 and 2 threads give the same
// bits, not just agreement to round-off.
TEST(Threads, OneAndTwoThreadsGiveIdenticalBits) {
  const std::vector<std::string> sorted = {"search.sort_every=50"};  // sorting takes part
  const World one = run("lattice_threads.toml", 1, sorted);
  const World two = run("lattice_threads.toml", 2, sorted);
  ASSERT_GT(one.contacts.pairs().size(), 4096u) << "the parallel contact loop must be exercised";
  EXPECT_TRUE(same_bits(one.particles.position, two.particles.position));
  EXPECT_TRUE(same_bits(one.particles.velocity, two.particles.velocity));
  EXPECT_TRUE(same_bits(one.particles.omega, two.particles.omega));
  const World again = run("lattice_threads.toml", 2, sorted);
  EXPECT_TRUE(same_bits(two.particles.position, again.particles.position));
}

// Rolling resistance (model EPSD, a history slot and a torque per contact, gathered with the
// contacts' other torques in the same order): 1 and 2 threads give the same bits, and the
// rolling torque changes the run.
TEST(Threads, RollingResistanceGivesIdenticalBitsForOneAndTwoThreads) {
  const std::vector<std::string> rolling = {"search.sort_every=50", "contact.default.rolling=\"epsd\"",
                                            "contact.default.rolling_friction=0.1", "contact.default.rolling_damping=0.3"};
  const World one = run("lattice_threads.toml", 1, rolling);
  const World two = run("lattice_threads.toml", 2, rolling);
  EXPECT_TRUE(same_bits(one.particles.position, two.particles.position));
  EXPECT_TRUE(same_bits(one.particles.velocity, two.particles.velocity));
  EXPECT_TRUE(same_bits(one.particles.omega, two.particles.omega));
  const World plain = run("lattice_threads.toml", 1, {"search.sort_every=50"});
  EXPECT_FALSE(same_bits(one.particles.omega, plain.particles.omega)) << "the rolling torque took no part";
}

// The same with block steps (grains settling in water onto a floor, tests/scenarios/
// block_sediment.toml): the rolling torques and their rates gathered in the same order, the
// rolling dashpot's correction and step bound alike on 1 and 2 threads.
TEST(Threads, RollingResistanceWithBlockStepsGivesIdenticalBitsForOneAndTwoThreads) {
  const std::vector<std::string> rolling = {"contact.default.rolling=\"epsd\"", "contact.default.rolling_friction=0.1",
                                            "contact.default.rolling_damping=0.3"};
  const World one = run("block_sediment.toml", 1, rolling);
  const World two = run("block_sediment.toml", 2, rolling);
  EXPECT_TRUE(testing::same_particle_bits(one, two));
  const World plain = run("block_sediment.toml", 1);
  EXPECT_FALSE(same_bits(one.particles.omega, plain.particles.omega)) << "the rolling torque took no part";
}

// Hindered settling (docs/engine.md): each grain's ball sums its neighbours in index order,
// so threads and the skin (which changes what the crowd list holds) leave the bits alone.
TEST(Threads, HinderedSettlingGivesIdenticalBitsForThreadsAndSkins) {
  const std::vector<std::string> water = {"search.sort_every=50", "fluid.density=1000", "fluid.kinematic_viscosity=1e-6",
                                          "fluid.hindered_settling=true"};
  auto with = [&](std::string extra) {
    std::vector<std::string> sets = water;
    sets.push_back(std::move(extra));
    return sets;
  };
  const World one = run("lattice_threads.toml", 1, with("simulation.skin=2e-5"));
  const World two = run("lattice_threads.toml", 2, with("simulation.skin=2e-5"));
  const World thick = run("lattice_threads.toml", 1, with("simulation.skin=8e-4"));
  const World plain = run("lattice_threads.toml", 1, {"search.sort_every=50", "fluid.density=1000",
                                                      "fluid.kinematic_viscosity=1e-6", "simulation.skin=2e-5"});
  for (const World* w : {&two, &thick}) {
    EXPECT_TRUE(same_bits(one.particles.position, w->particles.position));
    EXPECT_TRUE(same_bits(one.particles.velocity, w->particles.velocity));
    EXPECT_TRUE(same_bits(one.particles.omega, w->particles.omega));
  }
  EXPECT_FALSE(same_bits(one.particles.velocity, plain.particles.velocity)) << "the hindrance must act";
}

// Touching contacts are summed in (i, j) order whatever else the neighbour list holds, so the
// skin changes the number of list rebuilds, never the result.
TEST(NeighbourList, SkinDoesNotChangeTheResult) {
  const World thin = run("lattice_threads.toml", 1, {"simulation.skin=2e-5", "search.sort_every=50"});
  const World thick = run("lattice_threads.toml", 1, {"simulation.skin=8e-4", "search.sort_every=50"});
  EXPECT_TRUE(same_bits(thin.particles.position, thick.particles.position));
  EXPECT_TRUE(same_bits(thin.particles.velocity, thick.particles.velocity));
  EXPECT_TRUE(same_bits(thin.particles.omega, thick.particles.omega));
}

}  // namespace
}  // namespace tsubu
