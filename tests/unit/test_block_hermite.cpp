// Block-step Hermite integrator (docs/integrators.md): exactness on a parabola, fourth order
// on smooth problems, one forced level equal to a shared step of the same length, and the
// exact rates of the contact laws against central finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <string_view>
#include <vector>

#include "tsubu/contact/pair_geometry.hpp"
#include "tsubu/forces/evaluate.hpp"
#include "tsubu/sim/simulation.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

using testing::make_world;
using testing::spec_of;
using testing::Bed;

const Material kQuartz{"quartz", 2650, 1e9, 0.17};

BlockStepRules one_level(int level) {
  BlockStepRules r;
  r.levels = 8;
  r.force_level = level;
  return r;
}

std::uint64_t sum(const std::vector<std::uint64_t>& v) { return std::accumulate(v.begin(), v.end(), std::uint64_t{0}); }

Simulation run(Bed b, const BlockStepRules& rules, std::int64_t steps) {
  Simulation sim(std::move(b.world), std::move(b.model), Integrator::block_hermite, rules);
  sim.start();
  sim.advance_to(steps);
  return sim;
}

TEST(BlockHermite, FreeParabolaIsExact) {
  // dt = 0.5 ms: the grain moves at most 0.8 mm in a step, within the 2 mm its neighbour list
  // reaches, so that no rule but the force's smoothness limits the step.
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 5e-4, {0, 0, -9.81});
  auto& [w, model] = b;
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 1}, {0.3, -0.2, 1.5});
  const Simulation sim = run(std::move(b), {}, 100);
  const double t = 0.05;
  const Vec3 x = sim.world().particles.position[0], v = sim.world().particles.velocity[0];
  EXPECT_NEAR(x.x, 0.3 * t, 1e-14);
  EXPECT_NEAR(x.y, -0.2 * t, 1e-14);
  EXPECT_NEAR(x.z, 1 + 1.5 * t - 0.5 * 9.81 * t * t, 1e-14);
  EXPECT_NEAR(v.z, 1.5 - 9.81 * t, 1e-14);
  EXPECT_EQ(sim.block()->level_histogram()[0], 1u) << "no force rate: the largest step";
}

// A 1 mm quartz grain settling in water (drag, buoyancy, added mass), launched at
// `speed` downwards.
Bed settling_grain(double dt, double speed) {
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), dt, {0, 0, -9.81});
  auto& [w, model] = b;
  model.fluid.enabled = true;
  model.fluid.density = 1000;
  model.fluid.viscosity = 1e-6;
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0}, {0, 0, -speed});
  return b;
}
Bed settling_moving(double dt) { return settling_grain(dt, 0.05); }
Bed settling_from_rest(double dt) { return settling_grain(dt, 0); }

// A grain resting on a linear-spring floor (e = 1, no friction), started off its balance:
// it oscillates about delta_eq = m g / k without leaving the floor, delta(t) = delta_eq +
// A cos(omega t), omega = sqrt(k/m).
Bed oscillating_on_floor(double dt) {
  ContactSpec spec = spec_of("linear", "none", 1.0);
  spec.values.set("stiffness", 50.0);
  Bed b = make_world(kQuartz, spec, dt, {0, 0, -9.81});
  auto& [w, model] = b;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0.5e-3}, {});
  const double m = w.particles.mass[0], delta_eq = m * 9.81 / 50;
  w.particles.position[0].z = 0.5e-3 - delta_eq - 0.5 * delta_eq;  // A = delta_eq / 2
  return b;
}

double error_at(Bed (*make)(double), double dt, std::int64_t steps, const Vec3& exact_x, double scale) {
  const Simulation sim = run(make(dt), one_level(0), steps);
  return norm(sim.world().particles.position[0] - exact_x) / scale;
}

// Error ratios per halving of a shared step, position after t.
std::vector<double> ratios(Bed (*make)(double), double t, std::vector<int> steps, int reference) {
  const Vec3 exact = run(make(t / reference), one_level(0), reference).world().particles.position[0];
  std::vector<double> out;
  double last = 0;
  for (int n : steps) {
    const double e = norm(run(make(t / n), one_level(0), n).world().particles.position[0] - exact);
    if (last > 0) out.push_back(last / e);
    last = e;
  }
  return out;
}

TEST(BlockHermite, FourthOrderOnASettlingGrain) {
  // The fluid's forces are corrected at the corrected velocity (P(EC)^2), so a grain that is
  // already moving converges at fourth order.
  for (double r : ratios(settling_moving, 0.04, {16, 32, 64}, 2048)) {
    EXPECT_GT(r, 14);
    EXPECT_LT(r, 18);
  }
}

TEST(BlockHermite, FromRestTheDragLawLimitsTheOrder) {
  // Schiller-Naumann's Re^0.687 term has an unbounded second derivative at u = 0: released
  // from rest, the error falls as h^2.69 (ratio 2^2.687 = 6.4), whatever the integrator.
  for (double r : ratios(settling_from_rest, 0.04, {32, 64, 128}, 4096)) {
    EXPECT_GT(r, 5.5);
    EXPECT_LT(r, 7.5);
  }
}

TEST(BlockHermite, FourthOrderOnAHarmonicContact) {
  const World w0 = oscillating_on_floor(1).world;
  const double m = w0.particles.mass[0], omega = std::sqrt(50 / m), delta_eq = m * 9.81 / 50;
  const double t = 1.3 * 2 * M_PI / omega;
  const Vec3 exact{0, 0, 0.5e-3 - delta_eq - 0.5 * delta_eq * std::cos(omega * t)};
  double last = 0;
  for (int n : {64, 128, 256}) {
    const double e = error_at(oscillating_on_floor, t / n, n, exact, delta_eq);
    if (last > 0) {
      EXPECT_GT(last / e, 14) << n << " steps";
      EXPECT_LT(last / e, 18) << n << " steps";
    }
    last = e;
  }
}

// Four grains in a heap on a floor, with friction and damping: every particle forced onto
// level 2 of dt is the same run as level 0 of dt/4 (to the round-off of dt/4).
Bed heap(double dt) {
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), dt, {0, 0, -9.81});
  auto& [w, model] = b;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0.499e-3}, {});
  w.particles.add(1, 0, 1e-3, 2650, {0.9995e-3, 0, 0.4995e-3}, {0.01, 0, 0});
  w.particles.add(2, 0, 1e-3, 2650, {0.5e-3, 0.8e-3, 0.4999e-3}, {});
  w.particles.add(3, 0, 1e-3, 2650, {0.45e-3, 0.3e-3, 1.3e-3}, {0, 0, -0.05});
  return b;
}

TEST(BlockHermite, OneForcedLevelEqualsASharedStep) {
  const double dt = 2e-6;
  const Simulation fine = run(heap(dt / 4), one_level(0), 400);
  const Simulation coarse = run(heap(dt), one_level(2), 100);
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec3 a = fine.world().particles.position[i], b = coarse.world().particles.position[i];
    EXPECT_LT(norm(a - b), 1e-12 * 1e-3) << "particle " << i;
    EXPECT_LT(norm(fine.world().particles.velocity[i] - coarse.world().particles.velocity[i]), 1e-9) << i;
  }
  EXPECT_GT(fine.forces().evaluations(), 0u) << "the heap has contacts";
}

TEST(BlockHermite, DashpotsAreCorrectedToTheCorrectedVelocities) {
  // Two 0.5 mm grains resting side by side on the floor in water, one sliding into the
  // other (model H, alpha = 0.2, Mindlin friction): the fastest dashpot mode decays at
  // lambda up to ~1.8e6 1/s. Evaluated at the predicted velocities alone, the scheme is stable only
  // while lambda h < 0.61 (this pair blew up at h = 1 us); with the dashpots brought to the
  // corrected velocities, while lambda h < 2.5. At h = 1 us (lambda h ~ 1.8 by the rule of
  // ForceField::compute_active, which bounds lambda) the motion must die out.
  ContactSpec spec = spec_of("hertz_sediment", "mindlin", 0.5, 0.5);
  spec.values.set("alpha", 0.2);
  Bed b = make_world(kQuartz, spec, 1e-6 * 16, {0, 0, -9.81});
  auto& [w, model] = b;
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 0.5e-3, 2650, {0, 0, 0.2499e-3}, {0.01, 0, 0});
  w.particles.add(1, 0, 0.5e-3, 2650, {0.4999e-3, 0, 0.2499e-3}, {});
  const double energy0 = 0.5 * w.particles.mass[0] * 1e-4;
  const Simulation sim = run(std::move(b), one_level(4), 600);
  for (std::size_t i = 0; i < 2; ++i) {
    const Particles& p = sim.world().particles;
    const double energy = 0.5 * p.mass[i] * norm2(p.velocity[i]) + 0.5 * p.inertia[i] * norm2(p.omega[i]);
    EXPECT_LT(energy, 0.1 * energy0) << "particle " << i;
  }
}

// Twenty-seven 0.5 mm grains in three loose layers of nine, in a periodic column 2 mm wide
// in water, fall onto the floor (model H with alpha above its default of 0.2: the dashpots,
// not the springs, set the steps of grains in touch).
Bed settling_layers(double dt, double alpha) {
  ContactSpec spec = spec_of("hertz_sediment", "mindlin", 0.5, 0.5);
  spec.values.set("alpha", alpha);
  Bed b = make_world(kQuartz, spec, dt, {0, 0, -9.81});
  auto& [w, model] = b;
  w.domain = {{0, 0, 0}, {2e-3, 2e-3, 5e-3}, {true, true, false}};
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  const double r = 0.25e-3, spacing = 2e-3 / 3;
  std::uint64_t id = 0;
  for (int layer = 0; layer < 3; ++layer) {
    const double shift = layer == 1 ? 0.5 * spacing : 0.1 * spacing * layer;
    for (int ix = 0; ix < 3; ++ix)
      for (int iy = 0; iy < 3; ++iy)
        w.particles.add(id++, 0, r, 2650, {(ix + 0.3) * spacing + shift, (iy + 0.3) * spacing + shift, r + 0.02e-3 + 0.52e-3 * layer}, {});
  }
  return b;
}

double kinetic_energy(const Particles& p) {
  double e = 0;
  for (std::size_t i = 0; i < p.size(); ++i) e += 0.5 * p.mass[i] * norm2(p.velocity[i]) + 0.5 * p.inertia[i] * norm2(p.omega[i]);
  return e;
}

// The dashpots' rate measured along the run (damping_rate = "measured") against the block
// Gershgorin bound, which takes every contact's fastest direction (sliding and rolling at
// once, 7/2 eta_t) and adds up the contacts as if all acted on one mode: the grains in touch
// take half as many steps, and the bed is where it is with the bound, to a small fraction of
// its overlaps (about 1e-7 m here).
TEST(BlockHermite, TheDashpotsRateMeasuredAlongTheRunLengthensTheStepsOfADeposit) {
  BlockStepRules bound, measured;
  measured.damping_rate = DampingRate::measured;
  const Simulation a = run(settling_layers(1e-4, 0.6), bound, 300), b = run(settling_layers(1e-4, 0.6), measured, 300);
  const auto dashpot_set = [](const Simulation& s) { return s.block()->stats().set_by_own[static_cast<std::size_t>(StepRule::dashpot)]; };
  ASSERT_GT(dashpot_set(a), a.particle_force_evaluations() / 2) << "the bound sets most steps";
  EXPECT_LT(dashpot_set(b), dashpot_set(a) / 10);
  EXPECT_LT(b.particle_force_evaluations(), 0.6 * a.particle_force_evaluations());
  const Particles &pa = a.world().particles, &pb = b.world().particles;
  ASSERT_EQ(a.forces().totals(a.world()).contacts, b.forces().totals(b.world()).contacts);
  ASSERT_GE(a.forces().totals(a.world()).contacts, 18);
  for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_LT(norm(pa.position[i] - pb.position[i]), 1e-10) << "particle " << i;
  EXPECT_NEAR(kinetic_energy(pb), kinetic_energy(pa), 0.01 * kinetic_energy(pa));
}

// Two 0.5 mm grains resting side by side on the floor in water, one sliding into the other
// (model H with alpha = 2, ten times the default): the sliding grain's motion starts along
// the floor, its partner's from rest, and their fastest dashpot modes are set off as they
// press together. With the measured rate the steps follow them, and the motion dies out as
// with the bound; without a dashpot rule the pair overlaps by 11 % within 8 ms.
TEST(BlockHermite, WithTheMeasuredRateAnImpactOnTheFloorDiesOut) {
  for (DampingRate rate : {DampingRate::bound, DampingRate::measured}) {
    Bed b = settling_layers(1.6e-5, 2.0);
    b.world.particles = Particles{};
    b.world.particles.add(0, 0, 0.25e-3, 2650, {0.5e-3, 1e-3, 0.2499e-3}, {0.01, 0, 0});
    b.world.particles.add(1, 0, 0.25e-3, 2650, {0.9999e-3, 1e-3, 0.2499e-3}, {});
    const double energy0 = kinetic_energy(b.world.particles);
    BlockStepRules rules;
    rules.damping_rate = rate;
    const Simulation sim = run(std::move(b), rules, 600);
    EXPECT_LT(kinetic_energy(sim.world().particles), 0.1 * energy0) << (rate == DampingRate::bound ? "bound" : "measured");
  }
}

TEST(BlockHermite, AContactBetweenGrainsInTouchDoesNotTakeTheEventStep) {
  // Two 0.5 mm grains resting on the floor in water, one sliding into the other: both touch
  // the floor before their own contact begins, so its onset is no first touch from free
  // flight and the contact rules (about 0.8 us here), not eta_s |a|/|j| (~35 ns with model
  // H's dashpot), set the pair's step: level 6 (dt/64 = 156 ns) or coarser, and no
  // evaluation happens on level 8 or finer.
  ContactSpec spec = spec_of("hertz_sediment", "mindlin", 0.5, 0.5);
  Bed b = make_world(kQuartz, spec, 1e-5, {0, 0, -9.81});
  auto& [w, model] = b;
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 0.5e-3, 2650, {0, 0, 0.24999e-3}, {0.01, 0, 0});
  w.particles.add(1, 0, 0.5e-3, 2650, {0.50002e-3, 0, 0.24999e-3}, {});
  BlockStepRules rules;
  rules.levels = 20;
  Simulation sim(std::move(w), std::move(model), Integrator::block_hermite, rules);
  sim.start();
  int finest = 0, touching_steps = 0;
  for (std::int64_t step = 1; step <= 20; ++step) {
    sim.advance_to(step);
    bool touched = false;
    for (const Contact& c : sim.world().contacts.pairs()) touched = touched || c.touching;
    if (!touched) continue;
    ++touching_steps;
    for (int k = 0; k < 2; ++k) finest = std::max(finest, int(sim.block()->state().level[k]));
  }
  ASSERT_GT(touching_steps, 0) << "the grains met";
  EXPECT_LE(finest, 6);
  const auto& per_level = sim.block()->stats().evaluations;
  std::uint64_t fine = 0;
  for (std::size_t k = 8; k < per_level.size(); ++k) fine += per_level[k];
  EXPECT_EQ(fine, 0u) << "evaluations on level 8 (39 ns) or finer (18 with the event rule at this onset)";
}

TEST(BlockHermite, AGrainOnALongStepIsWokenBeforeAFastNeighbourReachesIt) {
  // A 2 mm grain at rest takes the longest step, dt = 4 ms; a 1 mm grain comes at 0.5 m/s
  // from 2 mm away, too far to be listed when the big one chose its step, and touches it
  // 1 ns before that step ends. The big grain must be woken and take short steps before the
  // contact begins: if the contact began inside its 4 ms step, the corrector would spread
  // the onset over that step. Checked by the collision's outcome: momentum kept, the big
  // grain no faster than an elastic collision makes it (2 m_s / (m_s + m_b) 0.5 m/s).
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 4e-3);
  auto& [w, model] = b;
  const double speed = 0.5, onset = 4e-3 - 1e-9;
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0}, {});
  w.particles.add(1, 0, 0.5e-3, 2650, {-1.5e-3 - speed * onset, 0, 0}, {speed, 0, 0});
  const double m_big = w.particles.mass[0], m_small = w.particles.mass[1];
  BlockStepRules rules;
  rules.levels = 24;
  Simulation sim = run(std::move(b), rules, 3);
  const Particles& p = sim.world().particles;
  ASSERT_GT(sim.block()->stats().wakes, 0u);
  const Vec3 momentum = m_big * p.velocity[0] + m_small * p.velocity[1];
  EXPECT_NEAR(momentum.x, m_small * speed, 1e-9 * m_small * speed);
  EXPECT_GT(p.velocity[0].x, 0.5 * 2 * m_small / (m_small + m_big) * speed) << "the grains met";
  EXPECT_LE(norm(p.velocity[0]), 2 * m_small / (m_small + m_big) * speed * (1 + 1e-6));
  EXPECT_LT(norm(p.velocity[1] - Vec3{p.velocity[1].x, 0, 0}), 1e-9) << "a head-on collision stays on its line";
}

TEST(BlockHermite, AGrainAddedCloseToAnotherTakesItsFirstStepFromTheGap) {
  // A grain enters the box (as an inflow adds it) 16 um above a smaller one that entered
  // before, catching it up at 0.027 m/s: they touch 0.6 ms later, inside the 1 ms steps
  // that free grains in water take. Evaluated at entry with its list, the new grain takes a
  // step from the gap and wakes the old one, and they meet on short steps. With the first
  // step chosen from the fluid alone both steps were 1 ms and the contact began inside them
  // (the poly example: 117 % overlap, the small grain flung off at 2 m/s; here the small
  // grain was thrown down at 6.4 m/s).
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, -9.81});
  auto& [w, model] = b;
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  w.particles.add(0, 0, 0.01, 2650, {0.02, 0.02, 0.005}, {});  // a grain elsewhere: the world is not empty
  BlockStepRules rules;
  Simulation sim(std::move(w), std::move(model), Integrator::block_hermite, rules);
  sim.start();
  sim.advance_to(1);
  Particles& p = sim.world().particles;
  const double ra = 0.78e-3, rb = 2.69e-3;
  p.add(1, 0, 2 * ra, 2650, {0, 0, 0.05}, {0, 0, -0.301});  // add() takes diameters
  sim.particles_added(1);
  sim.advance_to(3);  // the small grain falls on its own, on long steps
  p.add(2, 0, 2 * rb, 2650, p.position[1] + Vec3{0, 0, ra + rb + 16e-6}, p.velocity[1] - Vec3{0, 0, 0.027});
  sim.particles_added(2);
  ASSERT_NO_THROW(sim.advance_to(6));
  // The large grain settles faster: it catches the small one up and pushes it down, the two
  // riding together in a soft contact (overlap about 20 nm) at the same speed.
  EXPECT_NEAR(p.velocity[1].z, p.velocity[2].z, 1e-4);
  EXPECT_LT(std::abs(p.position[2].z - p.position[1].z - ra - rb), 1e-6);
  EXPECT_LT(std::hypot(p.velocity[1].x, p.velocity[1].y), 1e-9) << "a collision along z stays along z";
}

TEST(BlockHermite, FreeGrainsTakeLongStepsAndContactsShort) {
  // A grain falling through water far from a resting pair on the floor: the free grain
  // takes far longer steps than the pair in contact.
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, -9.81});
  auto& [w, model] = b;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0.499e-3}, {});
  w.particles.add(1, 0, 1e-3, 2650, {0.9995e-3, 0, 0.4995e-3}, {});
  w.particles.add(2, 0, 1e-3, 2650, {5e-3, 5e-3, 8e-3}, {});
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  BlockStepRules rules;
  rules.levels = 20;
  Simulation sim = run(std::move(b), rules, 4);
  // The pair's initial overlaps push it apart; after 4 steps grain 1 is on the floor (grain 0
  // may be lifted off it for a moment, depending on the friction law's transient).
  const HermiteState& s = sim.block()->state();
  ASSERT_FALSE(sim.world().contacts.walls().empty());
  EXPECT_GE(int(s.level[1]) - int(s.level[2]), 6) << "contact level " << int(s.level[1]) << ", free " << int(s.level[2]);
  for (const Contact& c : sim.world().contacts.pairs())
    if (c.touching) EXPECT_LE(std::abs(int(s.level[c.i]) - int(s.level[c.j])), rules.level_spread) << "partners in touch within the spread";
  for (const Contact& c : sim.world().contacts.walls())
    if (c.touching) EXPECT_GE(s.level[c.i], 6) << "a grain on the floor takes contact steps";
}

// run.json's account of what set the steps (BlockStepStats::set_by_own, set_by_cluster):
// every step chosen after an evaluation is counted once, by the rule that set its level. A
// 0.5 mm grain settles onto a 4 mm grain resting on the floor: the large grain's own
// contact rules set its steps until the small one lands; at the touch the newcomer's event
// rule sets its level, the large grain is raised to within the level spread of it, and its
// step is counted as set by its partner's rule. A lone grain settling through the water
// never takes a contact's rule.
TEST(BlockHermite, EveryStepIsCountedByTheRuleThatSetIt) {
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, -9.81});
  auto& [w, model] = b;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 4e-3, 2650, {0, 0, 1.999e-3}, {});
  w.particles.add(1, 0, 0.5e-3, 2650, {0, 0, 4.27e-3}, {});  // 20 um above the large grain
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  Simulation sim = run(std::move(b), BlockStepRules{}, 10);
  ASSERT_EQ(sim.forces().totals(sim.world()).contacts, 2) << "the small grain has landed";
  const BlockStepStats& st = sim.block()->stats();
  ASSERT_EQ(st.set_by_own.size(), kStepRules);
  EXPECT_EQ(sum(st.set_by_own) + sum(st.set_by_cluster), sim.particle_force_evaluations());
  const auto at = [](const std::vector<std::uint64_t>& v, StepRule r) { return v[static_cast<std::size_t>(r)]; };
  EXPECT_GT(at(st.set_by_own, StepRule::contact_or_gap) + at(st.set_by_own, StepRule::dashpot), 0u);
  EXPECT_GT(at(st.set_by_cluster, StepRule::event), 0u);

  Bed lone = settling_from_rest(1e-3);
  const Simulation alone = run(std::move(lone), BlockStepRules{}, 3);
  const BlockStepStats& sl = alone.block()->stats();
  EXPECT_EQ(sum(sl.set_by_cluster), 0u);
  EXPECT_EQ(at(sl.set_by_own, StepRule::dashpot), 0u);
  EXPECT_GT(at(sl.set_by_own, StepRule::fluid) + at(sl.set_by_own, StepRule::aarseth) + at(sl.set_by_own, StepRule::event), 0u);
}

// A 0.5 mm grain settles onto a 4 mm grain A resting on another, B, on the floor. With shared
// levels (level_spread 0) B takes the small grain's steps, since it touches A; with a spread
// B keeps the longer steps of its contacts with A and the floor, A takes the small grain's,
// and the landing ends where it ends with shared levels.
BlockStepRules spread_by(int levels) {
  BlockStepRules r;
  r.level_spread = levels;
  return r;
}
Bed small_grain_lands_on_a_stack() {
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, -9.81});
  auto& [w, model] = b;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 4e-3, 2650, {0, 0, 5.998e-3}, {});        // A
  w.particles.add(1, 0, 4e-3, 2650, {0, 0, 1.999e-3}, {});        // B
  w.particles.add(2, 0, 0.5e-3, 2650, {-2e-4, 0, 8.268e-3}, {});  // 20 um above A
  model.fluid.enabled = true, model.fluid.density = 1000, model.fluid.viscosity = 1e-6;
  return b;
}

TEST(BlockHermite, WithALevelSpreadGrainsInTouchKeepTheirOwnSteps) {
  const Simulation shared = run(small_grain_lands_on_a_stack(), spread_by(0), 30);
  const Simulation spread = run(small_grain_lands_on_a_stack(), spread_by(3), 30);
  ASSERT_EQ(spread.forces().totals(spread.world()).contacts, 3) << "the small grain has landed";
  const HermiteState &s = spread.block()->state(), &t = shared.block()->state();
  EXPECT_EQ(t.level[1], t.level[2]);
  EXPECT_EQ(int(s.level[2]) - int(s.level[1]), 3) << "B steps 8 times longer than the small grain";
  EXPECT_EQ(sum(spread.block()->stats().set_by_own) + sum(spread.block()->stats().set_by_cluster), spread.particle_force_evaluations());
  EXPECT_LT(spread.particle_force_evaluations(), 0.8 * shared.particle_force_evaluations());  // 58 911 against 82 869
  for (std::size_t i : {0u, 1u, 2u})
    EXPECT_LT(norm(spread.world().particles.position[i] - shared.world().particles.position[i]), 1e-9);  // 4e-10 m
}

// In vacuum momentum is exchanged only through the contacts: a 0.5 mm grain strikes a 4 mm
// grain A that touches another, B. With shared levels all three take the small grain's steps
// and the momentum after the collision is what the small grain brought to 7e-10 (the onset
// and release fits differ between partners); with a spread of 1-3 levels B takes A's force
// at its own, longer, step ends, 1e-5 to 2e-4; unbounded (20) 1.4e-2.
TEST(BlockHermite, WithALevelSpreadACollisionKeepsItsMomentum) {
  for (int spread : {0, 1, 2, 3, 20}) {
    Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, 0});
    auto& w = b.world;
    w.particles.add(0, 0, 4e-3, 2650, {0, 0, 0}, {});          // A
    w.particles.add(1, 0, 4e-3, 2650, {3.9999e-3, 0, 0}, {});  // B, 0.1 um into A
    w.particles.add(2, 0, 0.5e-3, 2650, {-2.3e-3, 0.3e-3, 0}, {0.2, 0, 0});
    const auto momentum = [](const Particles& p) {
      return p.mass[0] * p.velocity[0] + p.mass[1] * p.velocity[1] + p.mass[2] * p.velocity[2];
    };
    const Vec3 before = momentum(w.particles);
    const Simulation sim = run(std::move(b), spread_by(spread), 3);
    ASSERT_GT(sim.world().particles.velocity[0].x, 0) << "A was struck";
    const double error = norm(momentum(sim.world().particles) - before) / norm(before);
    EXPECT_LT(error, spread == 0 ? 2e-9 : spread <= 3 ? 1e-3 : 0.05) << "spread " << spread;
  }
}

// A floor that starts rising at 0.2 m/s under a grain 7.8 um above it (from the start, or
// within the grain's first step) carries the grain up at its speed, as velocity Verlet does.
// The steps chosen while the floor stood still once straddled the moment it started, the
// floor met the grain inside them, and the grain left at 11 to 99 m/s: a change of a wall's
// motion ends the steps of the grains that list it, and the gap rule sees the velocity the
// wall keeps from then on.
TEST(BlockHermite, AWallThatStartsMovingCarriesAGrainInsteadOfFlingingIt) {
  for (double starts : {0.0, 5e-4, 1.3e-3}) {
    Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, -9.81});
    auto& [w, model] = b;
    std::vector<WallMotion> motion = {{1.0, {0, 0, 0.2}}};
    if (starts > 0) motion.insert(motion.begin(), {starts, {}});
    w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, motion, {}});
    w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0.5078e-3}, {});
    const Simulation sim = run(std::move(b), BlockStepRules{}, 10);
    const Particles& p = sim.world().particles;
    EXPECT_NEAR(p.velocity[0].z, 0.2, 1e-3) << "floor starting at " << starts << " s";
    EXPECT_NEAR(p.position[0].z, 0.2 * (0.01 - starts) + 0.5e-3, 1e-6) << "floor starting at " << starts << " s";
  }
}

// A wall far from every grain that starts, turns and stops inside the block steps' intervals
// (nothing ends a step at its changes: no grain lists it) stays on its closed form. It moved
// by the velocity of each interval's midpoint over the whole interval and kept the error
// (here 0.2 m/s over up to a dt of 1 ms: 0.2 mm).
TEST(BlockHermite, AWallAwayFromTheGrainsStaysOnItsMotionsClosedForm) {
  Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, 0});
  auto& [w, model] = b;
  const std::vector<WallMotion> motion = {{1.3e-3, {}}, {4.71e-3, {0, 0, 0.2}}, {7.05e-3, {0, 0, -0.1}}};
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, motion, {}});
  w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0.02}, {});  // 20 mm above the floor, at rest: never near it
  const Simulation sim = run(std::move(b), BlockStepRules{}, 10);
  const double closed_form = 0.2 * (4.71e-3 - 1.3e-3) - 0.1 * (7.05e-3 - 4.71e-3);
  EXPECT_NEAR(sim.world().walls[0].point.z, closed_form, 1e-15);
}

// A frictionless head-on bounce with Tsuji's dashpot, at a touch phase where the contact
// opens just after a block time: the step in which it opens starts with the dashpot's rate
// near its singularity (it grows like delta^-3/4 as the overlap vanishes). The corrector
// fitted that rate, and the grain left at 0.441 m/s instead of the 0.400 that e = 0.8 and
// velocity Verlet give.
TEST(BlockHermite, ABounceWithTsujisDashpotLeavesAtItsRestitution) {
  const Material glass{"glass", 2500, 1e8, 0.3};
  Bed b = make_world(glass, spec_of("hertz_tsuji", "mindlin", 0.8, 0.0), 4.8270848315522534e-05);
  auto& [w, model] = b;
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
  w.particles.add(0, 0, 0.002, 2500, {0, 0, 0.0010084651360958798}, {0, 0, -0.5});
  const Simulation sim = run(std::move(b), BlockStepRules{}, 4);
  EXPECT_NEAR(sim.world().particles.velocity[0].z, 0.4, 0.4 * 0.02);
}

// The level a bound needs: the coarsest whose step dt/2^k is not above it; a bound that
// underflowed to zero, or is NaN, needs a level beyond any run's, never the coarsest.
TEST(BlockHermite, LevelNeededIsTheCoarsestNotAboveTheBound) {
  EXPECT_EQ(level_needed(1e-3, 2e-3), 0);
  EXPECT_EQ(level_needed(1e-3, 1e-3), 0);
  EXPECT_EQ(level_needed(1e-3, 0.5e-3), 1);
  EXPECT_EQ(level_needed(1e-3, 0.3e-3), 2);
  EXPECT_EQ(level_needed(1e-3, 1e-300), 987);        // ceil(log2(1e297))
  EXPECT_EQ(level_needed(1e-3, 1e-320), kBeyondLevels);  // dt/bound overflows
  EXPECT_EQ(level_needed(1e-3, 0.0), kBeyondLevels);
  EXPECT_EQ(level_needed(1e-3, -1.0), kBeyondLevels);
  EXPECT_EQ(level_needed(1e-3, std::nan("")), kBeyondLevels);
}

// Step-rule values so small (or u_floor so large) that a contact's step bound underflows
// put the grains in touch on the finest level, as any too-small bound does.
TEST(BlockHermite, StepRulesThatUnderflowGiveTheFinestLevel) {
  for (const char* rule : {"kappa_c", "eta_damping", "u_floor"}) {
    Bed b = make_world(kQuartz, spec_of("hertz_sediment", "mindlin", 0.5, 0.5), 1e-3, {0, 0, -9.81});
    auto& [w, model] = b;
    w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0, {}, {}});
    w.particles.add(0, 0, 1e-3, 2650, {0, 0, 0.499e-3}, {});
    w.particles.add(1, 0, 1e-3, 2650, {0.9995e-3, 0, 0.4995e-3}, {});
    BlockStepRules rules;
    rules.levels = 8;
    if (rule == std::string_view("kappa_c")) rules.kappa_c = 1e-320;
    if (rule == std::string_view("eta_damping")) rules.eta_damping = 1e-320;
    if (rule == std::string_view("u_floor")) rules.u_floor = 1e300;
    const Simulation sim = run(std::move(b), rules, 0);
    for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(sim.block()->state().level[i], 8) << rule << ": grain " << i;
  }
}

// Central difference of the force (and of the rolling torque) along x(t) = x0 + v t + a t^2/2,
// spin w(t) = w0 + alpha t, against the exact rate from the law run on Duals. The springs start
// from the same state on both sides and are stretched over +-h, as the scheme does over a step.
struct Body {
  Vec3 x, v, a, w, alpha;
  Body at(double t) const { return {x + t * v + (0.5 * t * t) * a, v + t * a, a, w + t * alpha, alpha}; }
};

constexpr double kRollingInertia = 3e-13;  // kg m^2, about the pair's below

template <class Normal, class Tangential, class Rolling = NoRolling>
ContactForceRate check_pair_rates(const Normal& normal, const Tangential& tangential, const Body& i, const Body& j, Vec3 xi0,
                                  const Rolling& rolling = {}, Vec3 spring0 = {}) {
  const double ri = 0.5e-3, rj = 0.6e-3, mi = 1.4e-6, mj = 2.4e-6;
  const Vec3 n0 = (i.x - j.x) / norm(i.x - j.x);
  xi0 -= dot(xi0, n0) * n0;  // the springs lie in the contact plane
  spring0 -= dot(spring0, n0) * n0;
  auto force = [&](double t, double dt) {
    const Body a = i.at(t), b = j.at(t);
    ContactGeometry g = pair_geometry<double>(ri, rj, mi, mj, a.x - b.x, a.v, b.v, a.w, b.w);
    g.dt = dt, g.rolling_inertia = kRollingInertia;
    ContactHistory h{xi0, {0, 0}, spring0};
    return evaluate(normal, tangential, rolling, g, h);
  };
  const Body a = i.at(0), b = j.at(0);
  DualContactGeometry g = pair_geometry<Dual>(ri, rj, mi, mj, DualVec3(a.x - b.x, a.v - b.v), DualVec3(a.v, a.a),
                                              DualVec3(b.v, b.a), DualVec3(a.w, a.alpha), DualVec3(b.w, b.alpha));
  g.dt = 0, g.rolling_inertia = kRollingInertia;
  ContactHistory h{xi0, {0, 0}, spring0};
  const ContactForceRate exact = evaluate_with_rates(normal, tangential, rolling, g, h);
  const double step = 1e-7;
  const ContactForce up = force(step, step), down = force(-step, -step);
  const Vec3 fd = (up.total - down.total) / (2 * step), fd_t = (up.tangential - down.tangential) / (2 * step);
  const double scale = norm(rate(exact.total));
  EXPECT_GT(scale, 0);
  EXPECT_LT(norm(fd - rate(exact.total)), 1e-5 * scale) << "total";
  EXPECT_LT(norm(fd_t - rate(exact.tangential)), 1e-5 * scale) << "tangential";
  if constexpr (!std::is_same_v<Rolling, NoRolling>) {
    const Vec3 fd_r = (up.rolling - down.rolling) / (2 * step), exact_r = rate(exact.rolling.torque);
    std::printf("rolling torque %.4g N m, its rate %.6g N m/s, off the difference by %.3g\n", norm(value(exact.rolling.torque)),
                norm(exact_r), norm(fd_r - exact_r));
    EXPECT_GT(norm(exact_r), 0);
    EXPECT_LT(norm(fd_r - exact_r), 1e-5 * norm(exact_r)) << "rolling";
  }
  return exact;
}

// Approaching, sliding sideways and spinning; the spring already stretched in the plane.
const Body kI{{1.05e-3, 0.02e-3, 0}, {-0.05, 0.02, 0.01}, {-3, 1, 0.5}, {10, -20, 5}, {100, 50, -30}};
const Body kJ{{0, 0, 0}, {0.02, -0.01, 0}, {1, 0, -2}, {-5, 8, 2}, {10, 0, 20}};

TEST(BlockHermiteRates, NormalLawsWithDamping) {
  const Vec3 none{};
  check_pair_rates(LinearDashpot{1e4, 0.3}, NoFriction{}, kI, kJ, none);
  check_pair_rates(HertzTsuji{5e8, HertzTsuji::alpha_of(0.5)}, NoFriction{}, kI, kJ, none);
  check_pair_rates(HertzSediment{5e8, 0.2}, NoFriction{}, kI, kJ, none);
}

TEST(BlockHermiteRates, TangentialStickAndSlip) {
  const Vec3 small{0, 1e-9, 2e-9}, large{0, 3e-5, -4e-5};  // below and beyond the slip limit
  check_pair_rates(LinearDashpot{1e4, 0.3}, LinearCoulomb{0.0, 0.9, 0.5, false}, kI, kJ, Vec3{});
  check_pair_rates(LinearDashpot{1e4, 0.0}, LinearCoulomb{0.8, 0.0, 0.5, false}, kI, kJ, small);
  for (const Vec3& xi : {small, large}) {
    check_pair_rates(HertzSediment{5e8, 0.2}, MindlinSlip{0.5, 0.17, 0.9}, kI, kJ, xi);
    check_pair_rates(HertzTsuji{5e8, 0.3}, LinearCoulomb{0.8, 0.9, 0.5, false}, kI, kJ, xi);
    check_pair_rates(LinearDashpot{1e4, 0.3}, LinearCoulomb{0.8, 0.9, 0.5, false}, kI, kJ, xi);
  }
}

// Rolling resistance on Duals: model CDT's torque turns with w_r's direction and follows the
// normal force; model EPSD's spring turns at -k_r w_r and with the contact plane, below its
// cap with the dashpot, at the cap (a spring already beyond it, slipping) without.
TEST(BlockHermiteRates, RollingResistance) {
  const HertzSediment normal{5e8, 0.2};
  const MindlinSlip tangential{0.5, 0.17, 0.9};
  const Vec3 xi{0, 1e-9, 2e-9};
  const ContactForceRate cdt = check_pair_rates(normal, tangential, kI, kJ, xi, ConstantDirectionalTorque{0.1});
  EXPECT_GT(norm(value(cdt.rolling.torque)), 0);
  const ElasticPlasticRolling epsd{0.1, 0.3};
  const ContactForceRate below = check_pair_rates(normal, tangential, kI, kJ, xi, epsd, Vec3{0, 1e-8, -2e-8});
  const ContactForceRate slipping = check_pair_rates(normal, tangential, kI, kJ, xi, epsd, Vec3{0, 1e-2, -2e-2});
  // The cap (mu_r R* |F_n|) lies between the two springs: the dashpot acts below it only.
  const double cap = norm(value(cdt.rolling.torque));
  std::printf("cap %.4g N m; below: spring dashpot C_r = %.4g N m s, k_r = %.4g N m; slipping: C_r = %.4g\n", cap,
              below.rolling.damping, below.rolling.stiffness, slipping.rolling.damping);
  EXPECT_GT(cap, norm(Vec3{0, 1e-8, -2e-8}));
  EXPECT_LT(cap, norm(Vec3{0, 1e-2, -2e-2}));
  EXPECT_GT(below.rolling.damping, 0);
  EXPECT_EQ(slipping.rolling.damping, 0);
  EXPECT_NEAR(norm(value(slipping.rolling.torque)), cap, 1e-12 * cap);
  EXPECT_GT(below.rolling.stiffness, 0);
}

TEST(BlockHermiteRates, WallContact) {
  const Vec3 n = Vec3{0.1, 0, 1} / norm(Vec3{0.1, 0, 1});
  const Vec3 wall_v{0.01, 0, 0.02};  // a moving wall
  const Body b{{0, 0, 0.45e-3}, {0.03, -0.02, -0.05}, {1, 2, -3}, {20, 10, -5}, {50, -30, 10}};
  const HertzSediment normal{5e8, 0.2};
  const MindlinSlip tangential{0.5, 0.17, 0.9};
  const double r = 0.5e-3, m = 1.4e-6;
  auto force = [&](double t, double dt) {
    const Body a = b.at(t);
    ContactGeometry g = wall_geometry<double>(r, m, n, dot(a.x - t * wall_v, n), a.v - wall_v, a.w);
    g.dt = dt;
    ContactHistory h{{0, 1e-9, 0}, {0, 0}};
    return evaluate(normal, tangential, NoRolling{}, g, h);
  };
  DualContactGeometry g = wall_geometry<Dual>(r, m, n, Dual(dot(b.x, n), dot(b.v - wall_v, n)),
                                              DualVec3(b.v - wall_v, b.a), DualVec3(b.w, b.alpha));
  ContactHistory h{{0, 1e-9, 0}, {0, 0}};
  const ContactForceRate exact = evaluate_with_rates(normal, tangential, NoRolling{}, g, h);
  const double step = 1e-7;
  const Vec3 fd = (force(step, step).total - force(-step, -step).total) / (2 * step);
  EXPECT_LT(norm(fd - rate(exact.total)), 1e-5 * norm(rate(exact.total)));
}

// A grain in contact with a wall that is not a whole plane, moving across it: the contact's
// normal turns, and the force's rate (touch_with_rates, as the block steps evaluate it) is
// the central difference of the force along the path: inside a turning drum (the point under
// the grain moves, and with it the surface's velocity), on a cone's outlet rim, on a hole's rim.
TEST(BlockHermiteRates, CurvedWallContact) {
  const double r = 0.5e-3, m = 1.4e-6;
  Wall drum;
  drum.shape = WallShape::cylinder, drum.axis = {0, 1, 0}, drum.radius = 0.01, drum.angular_velocity = {0, 3, 0};
  Wall cone;
  cone.shape = WallShape::cone, cone.axis = {0, 0, 1}, cone.radius = 0.01, cone.end_radius = 0.05, cone.length = 0.04;
  Wall plate;
  plate.normal = {0, 0, 1}, plate.hole_radius = 0.002;
  const Vec3 v{0.03, -0.02, -0.05}, a{20, 10, -5}, w{1, 2, -3}, alpha{50, -30, 10};
  const double deep = r - 0.45e-6;  // the centre's distance from the wall: touching
  const std::pair<Wall, Vec3> cases[] = {{drum, Vec3{0.3, 0, -0.954} * ((0.01 - deep) / norm(Vec3{0.3, 0, -0.954}))},
                                         {cone, Vec3{0.01, 0, 0} + deep * Vec3{-0.6, 0.0, -0.8}},
                                         {plate, Vec3{0.002, 0, 0} + deep * Vec3{-0.6, 0.0, 0.8}}};
  const HertzSediment normal{5e8, 0.2};
  const MindlinSlip tangential{0.5, 0.17, 0.9};
  for (const auto& [wall, x] : cases) {
    const Body b{x, v, a, w, alpha};
    auto force = [&](double t, double dt) {
      const Body at = b.at(t);
      const WallTouch touch = wall.touch(at.x);
      ContactGeometry g = wall_geometry<double>(r, m, touch.normal, touch.distance,
                                                at.v - wall.surface_velocity_at(at.x, touch), at.w);
      g.dt = dt;
      ContactHistory h{{0, 1e-8, 0}, {0, 0}};
      return evaluate(normal, tangential, NoRolling{}, g, h);
    };
    const Motion<Dual> motion{b.x, DualVec3(b.v, b.a), DualVec3(b.w, b.alpha)};
    const WallTouch touch = wall.touch(b.x);
    const DualVec3 v_rel = motion.v - surface_velocity<Dual>(wall, motion, touch);
    const BasicWallTouch<Dual> moving = touch_with_rates<Dual>(wall, motion, touch, v_rel);
    DualContactGeometry g = wall_geometry<Dual>(r, m, moving.normal, moving.distance, v_rel, motion.w);
    ContactHistory h{{0, 1e-8, 0}, {0, 0}};
    const ContactForceRate exact = evaluate_with_rates(normal, tangential, NoRolling{}, g, h);
    const double step = 1e-9;  // the spring (1e-8 m) changes by 5e-11 m: |xi| stays smooth
    const Vec3 fd = (force(step, step).total - force(-step, -step).total) / (2 * step);
    std::printf("shape %d: overlap %.3g m, force rate |%.6g| N/s, off the difference by %.3g\n", static_cast<int>(wall.shape),
                value(g.delta), norm(rate(exact.total)), norm(fd - rate(exact.total)));
    EXPECT_GT(value(g.delta), 0);
    // Measured 1e-9 to 1.3e-7; without the normal's rate 7e-6 to 5e-4.
    EXPECT_LT(norm(fd - rate(exact.total)), 1e-6 * norm(rate(exact.total)));
  }
}

}  // namespace
}  // namespace tsubu
