// Block-step Hermite integrator on whole runs (docs/integrators.md): an elastic bounce's
// energy over 100 bounces against velocity Verlet at the same number of particle force
// evaluations, and bit-identity across thread counts and search methods.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string_view>

#include "scenario_run.hpp"
#include "tsubu/app/simulation_state.hpp"
#include "tsubu/sim/simulation.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

using testing::make_world;
using testing::spec_of;
using testing::test_scenario;

// A 1 mm grain dropped from 10 um above a floor (impact 1.4 cm/s): no friction, no damping
// (e = 1), no fluid. Both laws are made soft enough for a contact time of about 0.5 ms
// (linear: k = 50 N/m, pi sqrt(m/k) = 0.52 ms; Hertz: E = 2.5 MPa), against 2.9 ms of flight,
// so that velocity Verlet at the block steps' number of evaluations still resolves contacts.
constexpr double kDrop = 1e-5, kRadius = 0.5e-3;

Simulation bouncing_grain(double dt, const char* normal, Integrator integrator) {
  ContactSpec spec = spec_of(normal, "none", 1.0);
  if (std::string_view(normal) == "linear") spec.values.set("stiffness", 50.0);
  auto [w, model] = make_world({"soft", 2650, 2.5e6, 0.17}, spec, dt, {0, 0, -9.81});
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 2 * kRadius, 2650, {0, 0, kRadius + kDrop}, {});
  return Simulation(std::move(w), std::move(model), integrator, BlockStepRules{});
}

struct Bounces {
  double drift = 0;  // (E - E0) / E0 after the last bounce, E = kinetic + m g z (out of contact)
  std::uint64_t evaluations = 0;
  double duration = 0;  // s
};

// Runs until the grain has passed `n` apexes (seen at the ends of dt, which a contact may fall
// between); the energy is read there, out of contact: kinetic and gravitational only.
Bounces bounce(Integrator integrator, double dt, const char* normal, int n) {
  Simulation sim = bouncing_grain(dt, normal, integrator);
  sim.start();
  const Particles& p = sim.world().particles;
  auto energy = [&] { return p.mass[0] * (0.5 * norm2(p.velocity[0]) + 9.81 * p.position[0].z); };
  const double e0 = energy();
  int apexes = 0;
  double last_vz = 0;
  while (apexes < n) {
    sim.step();
    apexes += last_vz > 0 && p.velocity[0].z <= 0;
    last_vz = p.velocity[0].z;
  }
  return {energy() / e0 - 1, sim.particle_force_evaluations(), sim.world().time};
}

class BlockHermiteBounce : public ::testing::TestWithParam<const char*> {};

// Block steps take dt = 1 ms (flight on the largest step, contacts on the levels the step
// rules choose); velocity Verlet gets the same number of particle force evaluations over the
// same time. Bound: |drift| < 1e-4 over 100 bounces, 1e-6 per bounce, an effective restitution
// within 5e-7 of 1: four orders below the loss of the most elastic real grains (e = 0.99 loses
// 2 % per bounce), so numerically irrelevant. Measured: linear 1.3e-5 (velocity Verlet
// 3.3e-3), Hertz -4.6e-5 (velocity Verlet -2.9e-5: no better, as Hertz's force has a second
// derivative that is unbounded at the contact's start and end, where a fourth-order scheme
// loses its order).
TEST_P(BlockHermiteBounce, EnergyDriftOverAHundredBounces) {
  const char* normal = GetParam();
  const Bounces block = bounce(Integrator::block_hermite, 1e-3, normal, 100);
  const double dt_vv = block.duration / static_cast<double>(block.evaluations);
  const Bounces vv = bounce(Integrator::velocity_verlet, dt_vv, normal, 100);
  std::printf("%s: block_hermite drift %.3e (%llu evaluations); velocity Verlet dt %.3g s: drift %.3e (%llu evaluations)\n",
              normal, block.drift, static_cast<unsigned long long>(block.evaluations), dt_vv, vv.drift,
              static_cast<unsigned long long>(vv.evaluations));
  ::testing::Test::RecordProperty("block_hermite_drift", std::to_string(block.drift));
  ::testing::Test::RecordProperty("velocity_verlet_drift", std::to_string(vv.drift));
  EXPECT_LT(std::abs(block.drift), 1e-4);
}

INSTANTIATE_TEST_SUITE_P(Laws, BlockHermiteBounce, ::testing::Values("linear", "hertz_tsuji"));

using testing::run_test_scenario;
using testing::same_bits;

void expect_same_run(const World& a, const World& b) {
  EXPECT_TRUE(same_bits(a.particles.position, b.particles.position));
  EXPECT_TRUE(same_bits(a.particles.velocity, b.particles.velocity));
  EXPECT_TRUE(same_bits(a.particles.omega, b.particles.omega));
}

// Each contact is evaluated once, from its first active particle, and each particle's forces
// are summed in contact order: 1 and 2 threads give the same bits. The scenario has more
// than 4096 particles, so the parallel loops engage when the free grains are all active.
TEST(BlockHermiteRuns, OneAndTwoThreadsGiveIdenticalBits) {
  const std::vector<std::string> sorted = {"search.sort_every=10"};  // the state is renumbered too
  const World one = run_test_scenario("block_threads.toml", sorted, 1);
  const World two = run_test_scenario("block_threads.toml", sorted, 2);
  ASSERT_GT(one.particles.size(), 4096u);
  std::size_t touching = 0;
  for (const Contact& c : one.contacts.pairs()) touching += c.touching;
  EXPECT_GT(touching, 100u) << "grains must collide";
  expect_same_run(one, two);
}

// With hindered settling each active grain's ball is summed in index order from the
// predicted neighbours: 1 and 2 threads give the same bits.
TEST(BlockHermiteRuns, HinderedSettlingOneAndTwoThreadsGiveIdenticalBits) {
  const std::vector<std::string> sets = {"search.sort_every=10", "fluid.hindered_settling=true"};
  const World one = run_test_scenario("block_threads.toml", sets, 1);
  const World two = run_test_scenario("block_threads.toml", sets, 2);
  expect_same_run(one, two);
}

// With a level spread the levels are brought within it in passes over the active set in its
// order, and a contact with an inactive partner is evaluated from the active side alone:
// 1 and 2 threads give the same bits.
TEST(BlockHermiteRuns, WithALevelSpreadOneAndTwoThreadsGiveIdenticalBits) {
  const std::vector<std::string> sets = {"search.sort_every=10", "simulation.block_steps.level_spread=2"};
  const World one = run_test_scenario("block_threads.toml", sets, 1);
  const World two = run_test_scenario("block_threads.toml", sets, 2);
  expect_same_run(one, two);
}

// The searches list the same pairs and the forces are summed in (i, j) order: the same bits
// with either method.
TEST(BlockHermiteRuns, CellAndMultilevelSearchGiveIdenticalBits) {
  const World cell = run_test_scenario("block_sediment.toml", {"search.method=\"cell\""});
  const World multi = run_test_scenario("block_sediment.toml", {"search.method=\"multilevel\""});
  std::size_t touching = 0;
  for (const Contact& c : cell.contacts.pairs()) touching += c.touching;
  EXPECT_GT(touching, 20u) << "grains must touch";
  expect_same_run(cell, multi);
}

// The contact records (forces, overlaps, elastic energy: what the contact network frames,
// the series and Python's contacts() read) follow their contacts through every new list:
// the lists built when inflow grains enter, at the end of a step, once left every contact
// but the new grains' with a zero force until its next evaluation.
TEST(BlockHermiteRuns, ContactRecordsSurviveTheEntryOfInflowGrains) {
  Simulation sim = new_simulation(test_scenario("rain_small.toml"));
  sim.start();
  int entries_among_contacts = 0;
  while (sim.world().step < 200) {
    const std::size_t before = sim.world().particles.size();
    sim.step();
    const std::vector<ContactRecord> records = sim.forces().touching_contacts(sim.world());
    if (records.empty()) continue;
    entries_among_contacts += sim.world().particles.size() > before;
    std::size_t without_force = 0;
    for (const ContactRecord& r : records) without_force += !(r.overlap > 0 && norm(r.normal_force) > 0);
    ASSERT_EQ(without_force, 0u) << "step " << sim.world().step << ": of " << records.size()
                                 << " touching contacts, these have no force";
    EXPECT_GT(sim.forces().totals(sim.world()).elastic_energy, 0);
  }
  EXPECT_GT(entries_among_contacts, 10) << "grains must enter while others touch";
}

}  // namespace
}  // namespace tsubu
