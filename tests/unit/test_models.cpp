// Contact models in isolation, against their formulas (docs/engine.md) with values
// computed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "tsubu/contact/law.hpp"

namespace tsubu {
namespace {

ContactGeometry touching(double delta, double v_n, Vec3 v_t = {}) {
  ContactGeometry g;
  g.n = {0, 0, 1};
  g.delta = delta;
  g.v_n = v_n;
  g.v_t = v_t;
  g.r_eff = 0.5e-3;
  g.m_eff = 2e-6;
  g.d_mean = 2e-3;
  g.dt = 1e-6;
  return g;
}

TEST(NormalModels, TsujiAlphaMatchesTheSpecValues) {
  EXPECT_NEAR(HertzTsuji::alpha_of(0.7), 0.252, 0.001);
  EXPECT_NEAR(HertzTsuji::alpha_of(0.5), 0.482, 0.001);
  EXPECT_NEAR(HertzTsuji::alpha_of(0.9), 0.075, 0.001);
  EXPECT_EQ(HertzTsuji::alpha_of(1.0), 0.0);
}

TEST(NormalModels, LinearDashpot) {
  const double k = 1e5, e = 0.5;
  const double beta = -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
  ContactHistory h;
  const NormalForce f = LinearDashpot{k, beta}.force(touching(1e-5, -0.1), h);
  const double eta = 2 * beta * std::sqrt(2e-6 * k);
  EXPECT_DOUBLE_EQ(f.f, k * 1e-5 + eta * 0.1);
  EXPECT_DOUBLE_EQ(f.energy, 0.5 * k * 1e-10);
  EXPECT_NEAR(beta, 0.215454, 1e-6);  // 0.693147 / sqrt(9.869604 + 0.480453)
}

TEST(NormalModels, HertzTsujiHandValues) {
  // E* = 1e9, R* = 0.5 mm: K = 4/3 1e9 sqrt(5e-4) = 2.98142397e7; delta = 1e-5:
  // elastic 2.98142397e7 * 3.16227766e-8 = 0.942809042 N.
  ContactHistory h;
  const NormalForce el = HertzTsuji{1e9, 0.0}.force(touching(1e-5, -0.1), h);
  EXPECT_NEAR(el.f, 0.942809042, 1e-8);
  EXPECT_NEAR(el.energy, 0.4 * 0.942809042 * 1e-5, 1e-14);
  EXPECT_NEAR(el.stiffness, 1.5 * 2.98142397e7 * std::sqrt(1e-5), 1e-2);
  // Damping alpha sqrt(m* K) delta^{1/4}: 0.482 * sqrt(2e-6 * 2.98142397e7) * 0.0562341325.
  const double alpha = HertzTsuji::alpha_of(0.5);
  const NormalForce d = HertzTsuji{1e9, alpha}.force(touching(1e-5, -0.1), h);
  EXPECT_NEAR(d.f - el.f, alpha * std::sqrt(2e-6 * 2.98142397e7) * 0.0562341325 * 0.1, 1e-9);
}

TEST(NormalModels, HertzSedimentHasAConstantDashpot) {
  ContactHistory h;
  const HertzSediment m{1e9, 0.2};
  const double K = 4.0 / 3.0 * 1e9 * std::sqrt(0.5e-3);
  const double eta = 0.2 * std::sqrt(K * 2e-6 * std::sqrt(2e-3));  // Sota & Watanabe Eq. 13
  for (double delta : {1e-7, 1e-5, 1e-4}) {
    const NormalForce f = m.force(touching(delta, -0.3), h);
    EXPECT_NEAR(f.damping, eta, 1e-12 * eta) << delta;
    EXPECT_NEAR(f.f, K * std::pow(delta, 1.5) + eta * 0.3, 1e-12 * f.f);
  }
}

TEST(NormalModels, EffectiveModuliOfTheSpec) {
  const Material a{"a", 1, 70e9, 0.3}, b{"b", 1, 200e9, 0.25};
  EXPECT_NEAR(effective_modulus(a, b), 1 / ((1 - 0.09) / 70e9 + (1 - 0.0625) / 200e9), 1);
  EXPECT_NEAR(effective_shear_modulus(a, b), 1 / (2 * 1.7 * 1.3 / 70e9 + 2 * 1.75 * 1.25 / 200e9), 1);
}

TEST(TangentialModels, SpringIsCarriedIntoTheTangentPlaneKeepingItsLength) {
  Vec3 xi{3e-6, 0, 4e-6};  // tilted out of the plane z = 0
  ContactGeometry g = touching(1e-5, 0);
  g.dt = 0;
  advance_spring(xi, g);
  EXPECT_NEAR(xi.z, 0, 1e-20);
  EXPECT_NEAR(norm(xi), 5e-6, 1e-18);
}

TEST(TangentialModels, LinearCoulombSticksThenSlides) {
  const LinearCoulomb model{0.8, 1.0, 0.5};
  NormalForce fn{10.0, 1e5, 0.0, 0.0};
  ContactGeometry g = touching(1e-5, 0, {0.1, 0, 0});
  g.dt = 1e-6;
  Vec3 xi;
  const Vec3 stick = model.force(g, fn, xi);  // |k_t xi| = 0.8e5 * 1e-7 = 8e-3 < 5 N
  EXPECT_NEAR(stick.x, -0.8e5 * 1e-7, 1e-12);
  Vec3 far{1e-3, 0, 0};  // k_t |xi| = 80 N > mu F_n = 5 N
  const Vec3 slide = model.force(g, fn, far);
  EXPECT_NEAR(slide.x, -5.0, 1e-12);
  EXPECT_NEAR(far.x, 5.0 / 0.8e5, 1e-15);  // spring reset to -F_t / k_t
}

TEST(TangentialModels, MindlinSlipCapAndPartialSlip) {
  const double mu = 0.5, sigma = 0.25, delta = 1e-5;
  const MindlinSlip model{mu, sigma, 0.0};
  const double xi_max = mu * (2 - sigma) / (2 * (1 - sigma)) * delta;  // Eq. 11
  NormalForce fn{3.0, 0, 0, 0, 2.0};  // the bound is the elastic part f_c^n = 2 N (Eq. 10), not the total 3 N
  ContactGeometry g = touching(delta, 0);
  g.dt = 0;
  Vec3 half{0.5 * xi_max, 0, 0};
  const Vec3 f_half = model.force(g, fn, half);
  EXPECT_NEAR(f_half.x, -mu * 2.0 * (1 - std::pow(0.5, 1.5)), 1e-12);  // chi = 1 - (1/2)^{3/2}
  Vec3 beyond{3 * xi_max, 0, 0};
  const Vec3 f_full = model.force(g, fn, beyond);
  EXPECT_NEAR(f_full.x, -mu * 2.0, 1e-12);  // full slip: mu |F_n|
  EXPECT_NEAR(beyond.x, xi_max, 1e-18);     // spring capped at xi_max
}

TEST(TangentialModels, MindlinBoundedReadingCapsTheWholeForce) {
  // A contact at half the slip stretch, sliding at 1 m/s with a strong tangential dashpot
  // (0.5 x 100 N s/m): as printed the dashpot comes on top of the spring's mu chi f_c^n;
  // bounded, the whole force is mu f_c^n, along the unbounded force.
  const double mu = 0.5, sigma = 0.25, delta = 1e-5;
  const double xi_max = mu * (2 - sigma) / (2 * (1 - sigma)) * delta;
  NormalForce fn{3.0, 0, 100.0, 0, 2.0};
  ContactGeometry g = touching(delta, 0, {1.0, 0.5, 0});
  g.dt = 0;
  Vec3 xi_printed{0.5 * xi_max, 0, 0}, xi_bounded = xi_printed;
  const Vec3 printed = MindlinSlip{mu, sigma, 0.5, false}.force(g, fn, xi_printed);
  const Vec3 bounded = MindlinSlip{mu, sigma, 0.5, true}.force(g, fn, xi_bounded);
  const Vec3 expected = Vec3{-mu * 2.0 * (1 - std::pow(0.5, 1.5)) - 50.0, -25.0, 0};
  EXPECT_NEAR(printed.x, expected.x, 1e-12);
  EXPECT_NEAR(printed.y, expected.y, 1e-12);
  EXPECT_NEAR(norm(bounded), mu * 2.0, 1e-12);
  EXPECT_NEAR(dot(bounded, expected) / (norm(bounded) * norm(expected)), 1.0, 1e-12);
  EXPECT_EQ(xi_bounded.x, xi_printed.x);  // the spring is the same either way
  // Below the bound the two readings are the same force.
  NormalForce slow = fn;
  slow.damping = 1e-3;
  Vec3 a{0.5 * xi_max, 0, 0}, b = a;
  const MindlinSlip as_printed{mu, sigma, 0.5, false}, bounded_law{mu, sigma, 0.5, true};
  EXPECT_EQ(as_printed.force(g, slow, a).x, bounded_law.force(g, slow, b).x);
  // friction = 0: frictionless when bounded, the bare dashpot as printed.
  Vec3 c{}, d{};
  const MindlinSlip frictionless_bounded{0.0, sigma, 0.5, true}, frictionless_printed{0.0, sigma, 0.5, false};
  EXPECT_EQ(norm(frictionless_bounded.force(g, fn, c)), 0.0);
  EXPECT_NEAR(norm(frictionless_printed.force(g, fn, d)), 50.0 * std::sqrt(1.25), 1e-12);
}

TEST(ContactLaws, RestitutionAndFrictionReachTheModels) {
  ContactSpec spec;
  spec.normal = "linear";
  spec.tangential = "linear_coulomb";
  spec.values.set("stiffness", 1e4);
  spec.restitution = 0.7;
  spec.friction = 0.3;
  const Material m{"m", 2500, 1e9, 0.3};
  const PairLaw law = make_pair_law(spec, m, m);
  const auto& n = std::get<LinearDashpot>(law.normal);
  const auto& t = std::get<LinearCoulomb>(law.tangential);
  EXPECT_EQ(n.k_n, 1e4);
  EXPECT_DOUBLE_EQ(n.beta, damping_ratio(0.7));
  EXPECT_DOUBLE_EQ(t.stiffness_ratio, 2 * 0.7 / 1.7);  // kappa = 2(1-nu)/(2-nu)
  EXPECT_DOUBLE_EQ(t.damping_ratio, std::sqrt(2 * 0.7 / 1.7));
  EXPECT_EQ(t.mu, 0.3);
}

}  // namespace
}  // namespace tsubu
