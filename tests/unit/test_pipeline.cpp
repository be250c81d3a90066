// The two evaluations of the force field agree: one state evaluated for a fixed step
// (ForceField::compute) and for block steps (ForceField::compute_active, every particle
// active) gives the same forces, torques and contact counts, bit for bit. Block steps
// evaluate at predicted kinematics; the fixed step is given those kinematics as its state.
// The one thing they do apart is the tangential spring's stretch over a step: the rectangle
// rule v_t dt for fixed steps, to second order from v_t's rate for block steps
// (tangential_models.hpp). So the laws are compared one step ahead without friction, and
// with it over a step of zero length.
#include <gtest/gtest.h>

#include <cmath>

#include "scenario_run.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

// A bed being poured onto the floor (grains in contact with each other and with the floor,
// others still falling), without a fluid; `edit` changes the scenario before the run,
// `edit_bed` the bed after it.
void compare_evaluations(const std::vector<std::string>& law, void (*edit)(Scenario&), void (*edit_bed)(World&),
                         bool frictionless) {
  std::vector<std::string> overrides = {"simulation.duration=0.06", "search.sort_every=0"};
  for (const std::string& key : law)  // a tangential law's own keys go with it
    if (!frictionless || key.find("friction_bound") == std::string::npos) overrides.push_back(key);
  Scenario sc = testing::test_scenario("settle_mono.toml", overrides);
  if (edit) edit(sc);
  if (frictionless) {
    sc.default_contact.tangential = "none";
    for (PairContactSpec& pair : sc.pair_contacts) pair.spec.tangential = "none";
  }
  Simulation sim(build_world(sc), build_model(sc), sc.integrator, sc.block_steps);
  sim.start();
  sim.advance_to(std::llround(sc.duration / sc.dt));
  World bed = sim.world();
  if (edit_bed) edit_bed(bed);
  const Model model = build_model(sc);
  const std::size_t n = bed.particles.size();

  // Each particle predicted one step dt ahead (with friction: none), with an acceleration and
  // a spin rate of its own.
  std::vector<std::int64_t> time(n, 0);
  std::vector<Vec3> acc(n), jerk(n), alpha(n), alpha_dot(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double s = static_cast<double>(i % 7) - 3;
    acc[i] = {0.1 * s, -0.2 * s, -9.81 + s};
    jerk[i] = {s, 2 * s, -s};
    alpha[i] = {3 * s, -s, 0.5 * s};
    alpha_dot[i] = {-s, s, 2 * s};
  }
  const Predictor kin{bed.particles, bed.domain, time, acc, jerk, alpha, alpha_dot, frictionless ? 1 : 0, bed.dt};

  World fixed = bed;
  if (!frictionless) fixed.dt = 0;  // the springs stretch by nothing in either
  for (std::size_t i = 0; i < n; ++i) {
    const Kinematics k = kin.at(i);
    fixed.particles.position[i] = k.x, fixed.particles.velocity[i] = k.v, fixed.particles.omega[i] = k.w;
  }
  ForceField fixed_field(model);
  fixed_field.compute(fixed);

  World block = bed;
  ForceField block_field(model);
  std::vector<Vec3> predicted(n);
  for (std::size_t i = 0; i < n; ++i) predicted[i] = kin.at(i).x;
  block_field.rebuild_at(block, predicted, std::vector<double>(n, 0.0), {});
  std::vector<std::uint32_t> active(n);
  for (std::size_t i = 0; i < n; ++i) active[i] = static_cast<std::uint32_t>(i);
  EvaluationRates rates;
  rates.resize(n);
  block_field.compute_active(block, kin, active, std::vector<char>(n, 1), ContactStepRules{1, 1, 0}, rates);

  ASSERT_EQ(fixed.contacts.pairs().size(), block.contacts.pairs().size());
  const ContactTotals totals = fixed_field.totals(fixed);
  ASSERT_GT(totals.contacts, n / 8) << "a bed with contacts";
  std::size_t on_floor = 0;
  for (const Contact& c : fixed.contacts.walls()) on_floor += c.touching;
  ASSERT_GT(on_floor, 0u) << "grains on the floor";
  EXPECT_EQ(totals.contacts, block_field.totals(block).contacts);
  EXPECT_TRUE(testing::same_bits(fixed.particles.force, block.particles.force));
  EXPECT_TRUE(testing::same_bits(fixed.particles.torque, block.particles.torque));
  EXPECT_EQ(fixed.particles.contact_count, block.particles.contact_count);
  // The histories alike (by value: a contact that has just opened keeps a spring of signed
  // zeros after a fixed step, of +0 after a block step; no law reads it before it closes).
  std::size_t differ = 0;
  auto same = [](const ContactHistory& a, const ContactHistory& b) {
    return a.xi == b.xi && a.normal[0] == b.normal[0] && a.normal[1] == b.normal[1];
  };
  for (std::size_t k = 0; k < fixed.contacts.pairs().size(); ++k)
    differ += !same(fixed.contacts.pairs()[k].history, block.contacts.pairs()[k].history);
  for (std::size_t k = 0; k < fixed.contacts.walls().size(); ++k)
    differ += !same(fixed.contacts.walls()[k].history, block.contacts.walls()[k].history);
  EXPECT_EQ(differ, 0u) << "histories advanced alike";
}

void expect_same_evaluations(const std::vector<std::string>& law, void (*edit)(Scenario&) = nullptr,
                             void (*edit_bed)(World&) = nullptr) {
  {
    SCOPED_TRACE("one step ahead, without friction");
    compare_evaluations(law, edit, edit_bed, true);
  }
  SCOPED_TRACE("the laws as given, over a step of zero length");
  compare_evaluations(law, edit, edit_bed, false);
}

TEST(Pipeline, FixedAndBlockStepEvaluationsGiveTheSameBitsHertzTsuji) { expect_same_evaluations({}); }

TEST(Pipeline, FixedAndBlockStepEvaluationsGiveTheSameBitsHertzSediment) {
  expect_same_evaluations({"contact.default.normal=\"hertz_sediment\"", "contact.default.friction_bound=\"total\""});
}

// A table of mixed model types: the floor is steel, with model H between glass and steel,
// the grains keep model T. Pairs and walls are evaluated each with its own law.
TEST(Pipeline, FixedAndBlockStepEvaluationsGiveTheSameBitsMixedLaws) {
  expect_same_evaluations({}, [](Scenario& sc) {
    sc.materials.push_back({"steel", 7800, 2e7, 0.28});
    for (Wall& w : sc.walls) w.material = 1;
    ContactSpec glass_steel;
    glass_steel.normal = "hertz_sediment";
    glass_steel.friction = 0.5;
    sc.pair_contacts.push_back({0, 1, glass_steel});
  });
}

// Grains of two materials with the same model types but their own parameters: every pair
// is evaluated with the law of its materials, whichever the evaluation. (The fixed steps
// once took the first material pair's law for every pair when the model types agreed.)
TEST(Pipeline, FixedAndBlockStepEvaluationsGiveTheSameBitsTwoGrainMaterials) {
  expect_same_evaluations(
      {}, [](Scenario& sc) { sc.materials.push_back({"stiff glass", 2500, 4 * sc.materials[0].youngs_modulus, 0.2}); },
      [](World& bed) {
        for (std::size_t i = 0; i < bed.particles.size(); i += 2) bed.particles.material[i] = 1;
      });
}

// A law defined on fixed steps only (here model P) cannot be evaluated for block steps: an
// error, never a skipped contact.
// Two 2 mm grains 0.1 mm into each other, at rest, with the law `normal` (+ no tangential
// law), evaluated as one block-step active set with `rules`: the rates, and the mass of each.
struct PairRates {
  EvaluationRates rates;
  double mass = 0;
};
PairRates evaluate_touching_pair(const char* normal, double restitution, const ContactStepRules& rules) {
  ContactSpec spec = testing::spec_of(normal, "none", restitution);
  spec.values.set("stiffness", 1000.0);
  auto [w, model] = testing::make_world({"grain", 2500, 1e7, 0.3}, spec, 1e-6);
  w.particles.add(0, 0, 0.002, 2500, {0, 0, 0}, {});
  w.particles.add(1, 0, 0.002, 2500, {0.0019, 0, 0}, {});
  ForceField field(model);
  field.rebuild_at(w, w.particles.position, {0, 0}, {});
  const std::vector<std::int64_t> time(2, 0);
  const std::vector<Vec3> zero(2);
  const Predictor kin{w.particles, w.domain, time, zero, zero, zero, zero, 1, 1e-6};
  PairRates out;
  out.rates.resize(2);
  out.mass = w.particles.mass[0];
  field.compute_active(w, kin, {0, 1}, {1, 1}, rules, out.rates);
  return out;
}

// The dashpots' decay rate for the step rule (the block Gershgorin sum
// max(eta_n, 7/2 eta_t) (1/m_i + 1/sqrt(m_i m_j)) of ForceField::compute_active): for a
// frictionless pair of equal grains, eta_t = 0, it is 2 eta_n / m, the exact decay rate of
// their relative normal velocity. (It once took 7/2 eta_n for every contact, as if the
// tangential dashpot were as strong as the normal one: 3.5 times too fast here.)
TEST(Pipeline, TheDashpotsRateIsTheirBlockGershgorinSum) {
  const double e = 0.5, k = 1000.0;
  const PairRates r = evaluate_touching_pair("linear", e, ContactStepRules{1e9, 0.5, 1e-3});  // no contact rule
  const double m = r.mass, beta = -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
  const double eta_n = 2 * beta * std::sqrt(0.5 * m * k);
  for (int i : {0, 1}) EXPECT_NEAR(r.rates.damping_rate[i], 2 * eta_n / m, 1e-12 * r.rates.damping_rate[i]);
}

TEST(Pipeline, BlockStepsRefuseALawWithoutRates) {
  try {
    evaluate_touching_pair("energy_conserving", 0.9, ContactStepRules{1, 1, 0});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("energy_conserving (P) has no rates"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tsubu
