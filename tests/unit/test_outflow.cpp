// Open faces of the box (docs/scenario.md, [domain] open): a grain whose centre crosses one
// leaves the run, recorded with its time, face and state; the other grains and their contact
// histories go on untouched; the same bits for any thread count; with fixed steps and with
// block steps (which remove a grain at the end of the step in which it crossed).
#include <gtest/gtest.h>

#include <cmath>

#include "scenario_run.hpp"
#include "tsubu/sim/outflow.hpp"
#include "tsubu/world/contact_list.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

void expect_a_grain_leaves_when_it_crosses(Integrator integrator) {
  const double g = 10, dt = 1e-3;
  auto [world, model] = testing::make_world({"glass", 2500, 1e7, 0.3}, testing::spec_of("hertz_tsuji", "none", 0.5), dt,
                                            {g, 0, 0});
  world.domain.open[0][1] = true;
  world.particles.add(1, 0, 0.01, 2500, {5, 0, 0}, {});
  world.particles.add(2, 0, 0.01, 2500, {-9, 0, 0}, {});
  Simulation sim(std::move(world), std::move(model), integrator, {});
  sim.start();
  sim.advance_to(1500);
  const char* name = integrator_name(integrator);
  const World& w = sim.world();
  ASSERT_EQ(w.particles.size(), 1u) << name;
  EXPECT_EQ(w.particles.id[0], 2) << name;
  const double t = 1.5;
  EXPECT_NEAR(w.particles.position[0].x, -9 + 0.5 * g * t * t, 1e-9) << name;
  ASSERT_NE(sim.outflow(), nullptr) << name;
  const std::vector<Departure> gone = sim.outflow()->take_departures();
  ASSERT_EQ(gone.size(), 1u) << name;
  const Departure& d = gone[0];
  EXPECT_EQ(d.id, 1) << name;
  EXPECT_EQ(kBoxFaces[static_cast<std::size_t>(d.face)], "x_max") << name;
  EXPECT_GE(d.time, 1.0 - 1e-12) << name;
  EXPECT_LE(d.time, 1.0 + dt + 1e-12) << name;
  EXPECT_NEAR(d.position.x, 5 + 0.5 * g * d.time * d.time, 1e-9) << name;
  const double drift = integrator == Integrator::block_hermite ? 0.0 : 0.5 * dt;
  EXPECT_NEAR(d.velocity.x, g * (d.time - drift), 1e-9) << name;
  EXPECT_EQ(sim.outflow()->totals().count, 1) << name;
  EXPECT_EQ(sim.outflow()->totals().mass, d.mass) << name;
  EXPECT_TRUE(sim.outflow()->take_departures().empty()) << name;  // each once
}

TEST(OpenFaces, ADomainSaysWhichOpenFaceAPositionHasCrossed) {
  Domain d{{0, 0, 0}, {1, 1, 1}, {false, true, false}};
  d.open[0][1] = true;  // x_max
  d.open[2][0] = true;  // z_min
  EXPECT_TRUE(d.any_open());
  EXPECT_EQ(d.departed({0.5, 0.5, 0.5}), -1);
  EXPECT_EQ(d.departed({1.1, 0.5, 0.5}), 1);
  EXPECT_EQ(d.departed({0.5, 0.5, -0.1}), 4);
  EXPECT_EQ(d.departed({-0.1, 0.5, 0.5}), -1);  // x_min is closed: lost, not departed
  EXPECT_FALSE(d.kept({-0.1, 0.5, 0.5}));
  EXPECT_TRUE(d.kept({1.1, 0.5, 1.5}));  // beyond a closed face too, but gone through an open one
  EXPECT_EQ(kBoxFaces[1], "x_max");
  EXPECT_EQ(kBoxFaces[4], "z_min");
}

// Particles ids 10, 11, 12 with pairs (10,11), (11,12), (10,12) and wall contacts of 10 and 12;
// 11 is removed: its pairs go, every other entry keeps its history and follows its particle.
TEST(OpenFaces, RemovingAParticleDropsItsContactsAndKeepsTheOthersHistories) {
  Particles p;
  for (int k = 0; k < 3; ++k) p.add(10 + k, 0, 1e-3, 2500, {0, 0, 1e-3 * k}, {});
  ContactList list;
  auto history = [](double x) { return ContactHistory{{x, 0, 0}, {x, 0}, {}}; };
  list.assign({{0, 1, true, history(1)}, {1, 2, true, history(2)}, {0, 2, true, history(3)}},
              {{0, 0, true, history(4)}, {2, 0, true, history(5)}}, p);
  Particles kept;
  kept.add(10, 0, 1e-3, 2500, {}, {});
  kept.add(12, 0, 1e-3, 2500, {}, {});
  list.renumber({0, ContactList::kGone, 1}, kept);
  ASSERT_EQ(list.pairs().size(), 1u);
  EXPECT_EQ(list.pairs()[0].i, 0u);
  EXPECT_EQ(list.pairs()[0].j, 1u);
  EXPECT_EQ(list.pairs()[0].history.xi.x, 3);
  EXPECT_EQ(list.pair_origin()[0], 1u);  // where it was in the list (by first id, then partner's): the records follow it
  ASSERT_EQ(list.walls().size(), 2u);
  EXPECT_EQ(list.walls()[1].i, 1u);
  EXPECT_EQ(list.walls()[1].history.xi.x, 5);
  EXPECT_EQ(list.wall_origin()[1], 1u);
}

// Two grains fall along +x under g = 10 m/s^2 from rest, at x = 5 and x = -9 in a box open at
// x = 10: the first crosses at t = sqrt(2 (10 - 5) / g) = 1 s and leaves; velocity Verlet
// moves a body under a constant force exactly (x_n = x_0 + g (n dt)^2 / 2 to round-off), so it
// is found at the first step past 1 s, with its last drift's velocity g (t - dt/2); the other
// falls on alone, as if nothing had happened. Block steps follow the parabola exactly too, and
// remove the grain at the end of the step in which it crossed, with its velocity g t.
TEST(OpenFaces, AGrainFallingThroughAnOpenFaceLeavesWhenItCrossesIt) {
  for (const Integrator integrator : {Integrator::velocity_verlet, Integrator::block_hermite})
    expect_a_grain_leaves_when_it_crosses(integrator);
}

// The chute of tests/scenarios/chute_open.toml: most grains leave through its open end, and
// 1 and 2 threads (with the spatial sort on, renumbering the grains as they go) end with the
// same grains, bits and totals; every grain is either in the box or counted as gone.
void expect_discharge_thread_invariant(std::vector<std::string> sets, std::int64_t at_least) {
  sets.push_back("search.sort_every=50");
  auto discharge = [&](int threads) {
    const Scenario sc = testing::test_scenario("chute_open.toml", sets);
    omp_set_num_threads(threads);
    Simulation sim(build_world(sc), build_model(sc), sc.integrator, sc.block_steps);
    const std::size_t created = sim.world().particles.size();
    sim.start();
    sim.advance_to(std::llround(sc.duration / sc.dt));
    omp_set_num_threads(1);
    const Outflow::Totals t = sim.outflow()->totals();
    EXPECT_EQ(static_cast<std::size_t>(t.count) + sim.world().particles.size(), created);
    return std::pair(std::move(sim.world()), t);
  };
  const auto [one, one_gone] = discharge(1);
  const auto [two, two_gone] = discharge(2);
  std::printf("%lld grains gone (%.6g kg), %zu left\n", static_cast<long long>(one_gone.count), one_gone.mass,
              one.particles.size());
  EXPECT_GT(one_gone.count, at_least);
  EXPECT_EQ(one_gone.count, two_gone.count);
  EXPECT_EQ(one_gone.mass, two_gone.mass);
  EXPECT_EQ(one.particles.id, two.particles.id);
  EXPECT_TRUE(testing::same_bits(one.particles.position, two.particles.position));
  EXPECT_TRUE(testing::same_bits(one.particles.velocity, two.particles.velocity));
  EXPECT_TRUE(testing::same_bits(one.particles.omega, two.particles.omega));
}

TEST(OpenFaces, AChuteDischargesWithTheSameBitsForOneAndTwoThreads) { expect_discharge_thread_invariant({}, 100); }

// The same with block steps (1 ms, to 0.12 s): grains that cross the face within a step fly
// on to its end and are removed there, on 1 and 2 threads alike.
TEST(OpenFaces, AChuteDischargesWithTheSameBitsForOneAndTwoThreads_BlockSteps) {
  expect_discharge_thread_invariant({"simulation.integrator=\"block_hermite\"", "simulation.dt=1e-3", "simulation.duration=0.12"},
                                    100);
}

}  // namespace
}  // namespace tsubu
