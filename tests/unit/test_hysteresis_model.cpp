// Model HH branch by branch with hand-computed values (docs/engine.md "Model HH"),
// the scenario keys that select it, and moving walls.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "tsubu/core/error.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

using Branch = HookeHysteresis::Branch;

// k_n = 1000 N/m, R* = 1 mm, k2max = 3000, k_c = 500, phi_f = 0.01:
// delta_lim = 3000/2000 * 0.01 * 2e-3 = 3e-5 m.
constexpr double kN = 1000, kR = 1e-3;
HookeHysteresis model() {
  HookeHysteresis m;
  m.c_k2 = 3;
  m.c_kc = 0.5;
  m.phi_f = 0.01;
  return m;
}

double hys(const HookeHysteresis& m, double delta, double& h, Branch& b) { return m.hysteresis(kN, kR, delta, h, &b); }

TEST(HookeHysteresis, PlasticityDepth) { EXPECT_NEAR(model().delta_lim(kN, kR), 3e-5, 1e-20); }

TEST(HookeHysteresis, VirginLoadingFollowsKn) {
  double h = 0;
  Branch b;
  EXPECT_NEAR(hys(model(), 1e-5, h, b), 0.01, 1e-15);  // k_n delta
  EXPECT_EQ(b, Branch::virgin);
  EXPECT_EQ(h, 1e-5);  // h = max(h, delta)
}

TEST(HookeHysteresis, UnloadingAndReloadingFollowK2) {
  // h = 2e-5: k2 = 1000 + 2000 * 2/3 = 7000/3.
  double h = 2e-5;
  Branch b;
  // delta = 1.5e-5: F = 7000/3 * (-5e-6) + 1000 * 2e-5 = 0.025/3.
  EXPECT_NEAR(hys(model(), 1.5e-5, h, b), 0.025 / 3, 1e-15);
  EXPECT_EQ(b, Branch::unload_reload);
  EXPECT_EQ(h, 2e-5);
  // Reloading to 1.8e-5 runs back up the same line: 7000/3 * (-2e-6) + 0.02 = 0.046/3.
  EXPECT_NEAR(hys(model(), 1.8e-5, h, b), 0.046 / 3, 1e-15);
  EXPECT_EQ(b, Branch::unload_reload);
  // Past h the virgin line takes over again.
  EXPECT_NEAR(hys(model(), 2.5e-5, h, b), 0.025, 1e-15);
  EXPECT_EQ(b, Branch::virgin);
  EXPECT_EQ(h, 2.5e-5);
}

TEST(HookeHysteresis, AdhesiveBranchRewritesTheHistory) {
  // h = 2e-5, delta = 5e-6: the k2 line gives 7000/3 * (-1.5e-5) + 0.02 = -0.015, below
  // -k_c delta = -0.0025, so F = -0.0025 and
  // h = (5e-6 + sqrt(2.5e-11 + 4 * 1500 * 5e-6 * 3e-5 / 2000))/2 = (5e-6 + sqrt(4.75e-10))/2.
  double h = 2e-5;
  Branch b;
  EXPECT_NEAR(hys(model(), 5e-6, h, b), -0.0025, 1e-15);
  EXPECT_EQ(b, Branch::adhesive);
  EXPECT_NEAR(h, 0.5 * (5e-6 + std::sqrt(4.75e-10)), 1e-18);
  EXPECT_NEAR(h, 1.3397e-5, 1e-9);
  // The new h puts this point on its own un/reloading line: k2(h)(delta - h) + k_n h = -k_c delta.
  const double k2 = kN + 2 * kN * h / 3e-5;
  EXPECT_NEAR(k2 * (5e-6 - h) + kN * h, -0.0025, 1e-15);
  // Reloading from the adhesive branch starts on that line.
  double h2 = h;
  EXPECT_NEAR(hys(model(), 8e-6, h2, b), k2 * (8e-6 - h) + kN * h, 1e-15);
  EXPECT_EQ(b, Branch::unload_reload);
  EXPECT_EQ(h2, h);
}

TEST(HookeHysteresis, BeyondThePlasticityDepthK2MaxWithoutUpperCap) {
  // h = 4e-5 >= delta_lim: F = 3000 (delta - 3e-5) + 1000 * 3e-5.
  double h = 4e-5;
  Branch b;
  EXPECT_NEAR(hys(model(), 3.5e-5, h, b), 0.045, 1e-15);  // above k_n delta = 0.035: no cap
  EXPECT_EQ(b, Branch::beyond_limit);
  EXPECT_NEAR(hys(model(), 4.5e-5, h, b), 0.075, 1e-15);  // loading beyond h stays on k2max
  EXPECT_EQ(h, 4.5e-5);
  // Adhesive branch in case A: 3000 * (-2e-5) + 0.03 = -0.03 < -0.005; then
  // h = (1e-5 + sqrt(1e-10 + 4 * 1500 * 1e-5 * 3e-5 / 2000))/2 = (1e-5 + sqrt(1e-9))/2 < delta_lim.
  h = 4e-5;
  EXPECT_NEAR(hys(model(), 1e-5, h, b), -0.005, 1e-15);
  EXPECT_EQ(b, Branch::adhesive);
  EXPECT_NEAR(h, 0.5 * (1e-5 + std::sqrt(1e-9)), 1e-18);
}

TEST(HookeHysteresis, WithoutAdhesionTheForceStopsAtZero) {
  HookeHysteresis m = model();
  m.c_kc = 0;
  double h = 2e-5;
  Branch b;
  EXPECT_EQ(m.hysteresis(kN, kR, 5e-6, h, &b), 0.0);
  EXPECT_EQ(b, Branch::adhesive);
  EXPECT_NEAR(h, 0.5 * (5e-6 + std::sqrt(2.5e-11 + 4 * 1000 * 5e-6 * 3e-5 / 2000)), 1e-18);
}

TEST(HookeHysteresis, LandryStiffnessAndDamping) {
  HookeHysteresis m = model();
  m.e_star = 1e6;
  m.v_c = 2;
  const double r = 1e-3, mass = 1e-5;
  // k_n = (16/15 sqrt(R*) E*)^{4/5} (m* v_c^2)^{1/5}, the same formula rearranged.
  const double expected = std::pow(16.0 / 15.0 * std::sqrt(r) * 1e6, 0.8) * std::pow(mass * 4, 0.2);
  EXPECT_NEAR(m.k_n(r, mass), expected, 1e-12 * expected);
  m.log_e = std::log(0.5);
  const double k = m.k_n(r, mass);
  // gamma_n = sqrt(4 m k/(1 + (pi/ln e)^2)) = 2 beta sqrt(m k) with beta = -ln e/sqrt(pi^2 + ln^2 e).
  EXPECT_NEAR(m.gamma_n(k, mass), 2 * damping_ratio(0.5) * std::sqrt(mass * k), 1e-12);
  m.log_e = 0;
  EXPECT_EQ(m.gamma_n(k, mass), 0.0);
}

TEST(HookeHysteresis, DampingAndTheNoTensionClamp) {
  HookeHysteresis m = model();
  m.e_star = 1e6;
  m.v_c = 1;
  m.log_e = std::log(0.5);
  ContactGeometry g;
  g.r_eff = kR;
  g.m_eff = 1e-5;
  const double k = m.k_n(g.r_eff, g.m_eff), gamma = m.gamma_n(k, g.m_eff);
  ContactHistory hist;
  g.delta = 1e-5;
  g.v_n = -0.1;  // approaching
  NormalForce fn = m.force(g, hist);
  EXPECT_NEAR(fn.f, k * 1e-5 + gamma * 0.1, 1e-15);
  EXPECT_EQ(fn.stiffness, k);
  EXPECT_EQ(fn.damping, gamma);
  // Pull apart deep into the adhesive branch: F_n = -k_c delta - gamma v_n < 0 ...
  g.delta = 1e-6;
  g.v_n = 0.1;
  ContactHistory copy = hist;
  EXPECT_LT(m.force(g, copy).f, 0);
  // ... unless tension is clamped away.
  m.no_tension = true;
  EXPECT_EQ(m.force(g, hist).f, 0.0);
}

TEST(HookeHysteresis, PairLawUsesKnForTheTangentialSpring) {
  ContactSpec spec = testing::spec_of("hooke_hysteresis", "linear_coulomb", 0.5, 0.3);
  spec.values.set("characteristic_velocity", 1.0);
  spec.values.set("max_stiffness_ratio", 2.0);
  spec.values.set("plasticity_depth", 0.05);
  const Material glass{"glass", 2500, 1e7, 0.3};
  PairLaw law = make_pair_law(spec, glass, glass);
  const auto& t = std::get<LinearCoulomb>(law.tangential);
  EXPECT_EQ(t.stiffness_ratio, 1.0);
  EXPECT_EQ(t.damping_ratio, 1.0);
  EXPECT_TRUE(t.projected);
  spec.values.set("tangential_damping", false);
  law = make_pair_law(spec, glass, glass);
  EXPECT_EQ(std::get<LinearCoulomb>(law.tangential).damping_ratio, 0.0);
  spec.values.set("max_stiffness_ratio", 1.0);
  EXPECT_THROW(make_pair_law(spec, glass, glass), std::invalid_argument);
}

// A scenario with model HH and a moving wall loads, and --set reaches the new keys.
TEST(HookeHysteresis, ScenarioKeys) {
  const auto path = std::filesystem::temp_directory_path() / "tsubu_hh_keys.toml";
  std::ofstream(path) << R"([simulation]
duration = 0.01
dt = 1e-6
gravity = [0, 0, 0]
[domain]
lower = [0, 0, 0]
upper = [0.01, 0.01, 0.01]
[[materials]]
name = "clay"
density = 2000
youngs_modulus = 1e7
poisson = 0.3
[contact.default]
normal = "hooke_hysteresis"
restitution = 0.5
friction = 0.3
characteristic_velocity = 0.5
max_stiffness_ratio = 4
adhesion_stiffness_ratio = 0.2
plasticity_depth = 0.05
no_tension = true
tangential_damping = false
[[walls]]
point = [0, 0, 0.008]
normal = [0, 0, -1]
material = "clay"
motion = [{ until = 0.004, velocity = [0, 0, -0.1] }, { until = 0.008, velocity = [0, 0, 0.1] }]
[[particles]]
source = "lattice"
material = "clay"
lower = [0, 0, 0]
upper = [0.004, 0.004, 0.004]
diameter = 0.002
)";
  const Scenario sc = load_scenario(path.string());
  const ContactSpec& c = sc.default_contact;
  EXPECT_EQ(c.normal, "hooke_hysteresis");
  EXPECT_EQ(c.tangential, "linear_coulomb");  // the default with HH
  EXPECT_EQ(c.values.number("characteristic_velocity"), 0.5);
  EXPECT_EQ(c.values.number("max_stiffness_ratio"), 4);
  EXPECT_EQ(c.values.number("adhesion_stiffness_ratio"), 0.2);
  EXPECT_EQ(c.values.number("plasticity_depth"), 0.05);
  EXPECT_TRUE(c.values.flag("no_tension"));
  EXPECT_FALSE(c.values.flag("tangential_damping"));
  ASSERT_EQ(sc.walls.size(), 1u);
  ASSERT_EQ(sc.walls[0].motion.size(), 2u);
  EXPECT_EQ(sc.walls[0].motion[1].until, 0.008);
  EXPECT_EQ(sc.walls[0].motion[1].velocity.z, 0.1);
  try {
    load_scenario(path.string(), {"contact.default.max_stiffness_ratio=1.0"});
    ADD_FAILURE() << "max_stiffness_ratio = 1 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("contact.default.max_stiffness_ratio: is k2max/k_n and must be > 1"),
              std::string::npos)
        << e.what();
  }
  try {
    load_scenario(path.string(), {"walls.0.motion.1.until=0.003"});
    ADD_FAILURE() << "a stretch ending before the previous one was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("until: must be later than the end of the previous stretch"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

// A wall moving at constant speed: its point follows v t, stands still after the last
// stretch, and its velocity enters the contact: a resting sphere touched by an approaching
// wall feels the damping of the approach speed.
TEST(MovingWall, FollowsItsStretchesAndCarriesItsVelocity) {
  const Material m{"grain", 2500, 1e7, 0.3};
  ContactSpec spec = testing::spec_of("linear", "none", 0.5);
  spec.values.set("stiffness", 1000.0);
  auto [w, model] = testing::make_world(m, spec, 1e-6);
  Wall plate{{0, 0, 0.00105}, {0, 0, -1}, 0};
  plate.motion = {{2e-4, {0, 0, -0.5}}, {3e-4, {0, 0, 0.25}}};
  w.walls.push_back(plate);
  w.particles.add(0, 0, 0.002, 2500, {0, 0, 0}, {});
  ForceField f(model);
  f.compute(w);
  EXPECT_EQ(w.particles.force[0].z, 0.0);
  bool saw_first_touch = false;
  for (int s = 0; s < 400; ++s) {
    const double before = w.walls[0].point.z;
    velocity_verlet_step(w, testing::evaluation(f, w));
    const double expected_v = s < 200 ? -0.5 : s < 300 ? 0.25 : 0.0;
    EXPECT_EQ(w.walls[0].velocity.z, expected_v) << "step " << s + 1;
    EXPECT_NEAR(w.walls[0].point.z - before, expected_v * 1e-6, 1e-18);
    if (!saw_first_touch && f.totals(w).contacts > 0) {
      saw_first_touch = true;
      // The sphere was at rest until this step (its half-step velocity is 0), the wall
      // approaches at 0.5 m/s: v_n = (v_i - v_wall).n = -0.5.
      const double eta = 2 * damping_ratio(0.5) * std::sqrt(w.particles.mass[0] * 1000);
      const double delta = 0.001 - (w.walls[0].point.z - w.particles.position[0].z);
      EXPECT_NEAR(f.wall_load(w, 0), 1000 * delta + eta * 0.5, 1e-12);
    }
  }
  EXPECT_TRUE(saw_first_touch);
  EXPECT_NEAR(w.walls[0].point.z, 0.00105 - 0.5 * 2e-4 + 0.25 * 1e-4, 1e-15);
}

}  // namespace
}  // namespace tsubu
