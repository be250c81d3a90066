// Still-fluid forces (docs/engine.md, "Fluid forces"): coefficients, Rubey's speed, and the
// time derivatives of every force and torque against central finite differences.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "tsubu/fluid/fluid.hpp"

namespace tsubu {
namespace {

constexpr double kRhoF = 1000, kNu = 1e-6;

Fluid water() {
  Fluid f;
  f.enabled = true;
  f.density = kRhoF;
  f.viscosity = kNu;
  return f;
}

Fluid only(bool buoyancy, bool drag, bool torque, SpinModel lift = SpinModel::none) {
  Fluid f = water();
  f.buoyancy = buoyancy;
  f.drag = drag;
  f.stokes_torque = torque;
  f.lift = lift;
  return f;
}

TEST(FluidCoefficients, SchillerNaumannWithCap) {
  EXPECT_NEAR(drag_coefficient(1.0), 24 * 1.15, 1e-12);
  EXPECT_NEAR(drag_coefficient(100.0), 0.24 * (1 + 0.15 * std::pow(100.0, 0.687)), 1e-12);
  EXPECT_NEAR(drag_coefficient(1000.0), 0.024 * (1 + 0.15 * std::pow(1000.0, 0.687)), 1e-12);
  EXPECT_EQ(drag_coefficient(1000.001), 0.44);
  EXPECT_EQ(drag_coefficient(1e5), 0.44);
  // The plain formula would overshoot above 1000; the cap is within 0.5% of it at the kink.
  EXPECT_NEAR(drag_coefficient(1000.0), 0.44, 0.005 * 0.44);
}

TEST(FluidCoefficients, LothLift) {
  // Rr (1 - (0.675 + 0.15 (1 + tanh(0.28 (Rr - 2)))) tanh(0.18 Re^0.5)), written out.
  const double re = 50, rr = 0.3;
  const double expect = rr * (1 - (0.675 + 0.15 * (1 + std::tanh(0.28 * (rr - 2)))) * std::tanh(0.18 * std::sqrt(re)));
  EXPECT_NEAR(loth_lift_coefficient(re, rr), expect, 1e-15);
  EXPECT_NEAR(loth_lift_coefficient(0, rr), rr, 1e-15);  // the low-Re limit C_L = Rr
}

TEST(FluidCoefficients, EtaTableIsPiecewiseLinearAndHeld) {
  const std::vector<double> re{1, 10, 100}, v{0.5, 1.0, 3.0};
  EXPECT_EQ(eta_at(re, v, 0.2), 0.5);
  EXPECT_EQ(eta_at(re, v, 500), 3.0);
  EXPECT_NEAR(eta_at(re, v, 5.5), 0.75, 1e-15);
  EXPECT_NEAR(eta_at(re, v, 55), 2.0, 1e-15);
  EXPECT_EQ(eta_at({}, {}, 55), 0.0);
}

TEST(FluidCoefficients, RubeySpeed) {
  // 1 cm quartz in water: about 0.33 m/s (docs/sedimentation.md), by the formula written out.
  const double g = 9.81, s1 = 1.65, d = 0.01;
  const double dstar = s1 * g * d * d * d / (kNu * kNu);
  const double expect = std::sqrt(s1 * g * d) * (std::sqrt(2.0 / 3 + 36 / dstar) - std::sqrt(36 / dstar));
  EXPECT_NEAR(rubey_speed(2650, kRhoF, kNu, d, g), expect, 1e-14);
  EXPECT_NEAR(rubey_speed(2650, kRhoF, kNu, d, g), 0.328, 0.001);
  // The Stokes limit for fine grains: (s-1) g d^2 / (18 nu).
  const double fine = 1e-5;
  EXPECT_NEAR(rubey_speed(2650, kRhoF, kNu, fine, g), s1 * g * fine * fine / (18 * kNu), 0.01 * s1 * g * fine * fine / (18 * kNu));
}

TEST(FluidForces, BuoyancyDragTorqueAndAddedMass) {
  const Fluid f = water();
  const double d = 1e-3, area = M_PI * d * d / 4, volume = M_PI * d * d * d / 6;
  const Vec3 g{0, 0, -9.81};
  const Vec3 u{0.03, 0.0, -0.04};  // |u| = 0.05, Re = 50
  const Vec3 w{0, 200, 0};
  const FluidLoad l = fluid_load(f, d, g, u, w);
  const double cd = drag_coefficient(50);
  const Vec3 expect = -kRhoF * volume * g - (0.5 * cd * kRhoF * area * 0.05) * u;
  EXPECT_NEAR(norm(l.force - expect), 0, 1e-12 * norm(expect));
  const Vec3 torque = -M_PI * kRhoF * kNu * d * d * d * w;
  EXPECT_NEAR(norm(l.torque - torque), 0, 1e-12 * norm(torque));
  EXPECT_NEAR(f.added_mass_of(d), 0.5 * kRhoF * volume, 1e-18);
  Fluid off = f;
  off.enabled = false;
  EXPECT_EQ(off.added_mass_of(d), 0.0);
  EXPECT_EQ(fluid_load(off, d, g, u, w).force, Vec3{});
}

// The fixed-step evaluation takes the loads of a batch of grains at once (fluid_loads): the
// same bits as one grain's fluid_load, for every switch of the fluid, at rest (the Stokes
// limit), at speeds whose square underflows, above the drag's cap, hindered and not.
TEST(FluidForces, ABatchIsEachGrainsLoadToTheBit) {
  std::vector<Fluid> fluids;
  for (int bits = 0; bits < 16; ++bits) {
    Fluid f = only(bits & 1, bits & 2, bits & 4);
    f.drag_cap = bits & 8;
    fluids.push_back(f);
    f.hindered = true;
    fluids.push_back(f);
  }
  fluids.push_back(only(true, true, true, SpinModel::loth));
  Fluid off = water();
  off.enabled = false;
  fluids.push_back(off);
  const std::size_t n = 150;  // more than one batch
  std::vector<double> d(n);
  std::vector<Vec3> u(n), w(n);
  std::vector<Crowding> crowd(n);
  std::uint64_t state = 12345;
  const auto uniform = [&] {  // in [-1, 1)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-52 - 1.0;
  };
  for (std::size_t k = 0; k < n; ++k) {
    d[k] = 1e-3 * (5.5 + 4.5 * uniform());
    const double speed = k % 10 == 0 ? 0.0 : k % 10 == 1 ? 1e-170 : k % 10 == 2 ? 2.0 : 0.3;
    u[k] = speed * Vec3{uniform(), uniform(), uniform()};
    w[k] = k % 7 == 0 ? Vec3{} : 300 * Vec3{uniform(), uniform(), uniform()};
    if (k % 3 != 0) crowd[k] = {0.3 * (1 + uniform()), uniform(), 4.65};
  }
  const Vec3 g{0, 0, -9.81};
  std::vector<FluidLoad> batch(n);
  for (const Fluid& f : fluids) {
    fluid_loads(f, g, n, d.data(), u.data(), w.data(), crowd.data(), batch.data());
    for (std::size_t k = 0; k < n; ++k) {
      const FluidLoad one = fluid_load(f, d[k], g, u[k], w[k], crowd[k]);
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(batch[k].force[c]), std::bit_cast<std::uint64_t>(one.force[c]))
            << "grain " << k << ", axis " << c << ", drag " << f.drag << ", hindered " << f.hindered;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(batch[k].torque[c]), std::bit_cast<std::uint64_t>(one.torque[c]));
      }
    }
  }
}

TEST(FluidForces, LiftAlongOmegaCrossU) {
  Fluid f = only(false, false, false, SpinModel::loth);
  const double d = 1e-3, area = M_PI * d * d / 4;
  const Vec3 u{0.05, 0, 0}, w{0, 0, 30};  // Re = 50, Rr = d |w| / |u| = 0.6
  const FluidLoad l = fluid_load(f, d, {}, u, w);
  const double cl = loth_lift_coefficient(50, 0.6);
  EXPECT_NEAR(l.force.y, 0.5 * cl * kRhoF * area * 0.05 * 0.05, 1e-15);  // w x u = +y
  EXPECT_NEAR(l.force.x, 0, 1e-18);
  EXPECT_NEAR(l.force.z, 0, 1e-18);

  f.lift = SpinModel::kurose_komori;
  f.eta = {{1, 100}, {0.2, 0.4}, {1.0, 2.0}, {0.5, 0.7}};
  f.drag = true;
  const FluidLoad k = fluid_load(f, d, {}, u, w);
  const double star = d * 30 / (2 * 0.05);  // 0.3
  const double e1 = 0.2 + 0.2 * 49 / 99, e2 = 1 + 49.0 / 99, e3 = 0.5 + 0.2 * 49 / 99;
  const double cd = (1 + e1 * std::sqrt(star) + e2 * std::pow(star, 4)) * drag_coefficient(50);
  EXPECT_NEAR(k.force.x, -0.5 * cd * kRhoF * area * 0.05 * 0.05, 1e-15);
  EXPECT_NEAR(k.force.y, 0.5 * e3 * star * kRhoF * area * 0.05 * 0.05, 1e-15);
  // Omega* beyond 0.5 is held at 0.5.
  const FluidLoad held = fluid_load(f, d, {}, u, {0, 0, 200});
  const double cl_half = 0.5 * e3;
  EXPECT_NEAR(held.force.y, 0.5 * cl_half * kRhoF * area * 0.05 * 0.05, 1e-15);
}

// A smooth trajectory through (u0, w0) at t = 0.
struct Path {
  Vec3 u0, a, b, w0, alpha, beta;
  Vec3 u(double t) const { return u0 + t * a + (0.5 * t * t) * b; }
  Vec3 w(double t) const { return w0 + t * alpha + (0.5 * t * t) * beta; }
};

// Largest difference between the analytic rates and a central difference over +-h, relative
// to the size of the rate; the force and torque are checked separately.
void expect_rates_match(const Fluid& f, double d, const Path& p, double h, double tol, const char* what) {
  const Vec3 g{0, 0, -9.81};
  const FluidLoad plus = fluid_load(f, d, g, p.u(h), p.w(h));
  const FluidLoad minus = fluid_load(f, d, g, p.u(-h), p.w(-h));
  const FluidLoad rate = fluid_load_rate(f, d, p.u0, p.a, p.w0, p.alpha);
  const Vec3 fd_force = (plus.force - minus.force) / (2 * h);
  const Vec3 fd_torque = (plus.torque - minus.torque) / (2 * h);
  EXPECT_GT(norm(rate.force), 0) << what;
  std::printf("rate check, %s: relative difference to the central difference %.2e (force), %.2e (torque)\n", what,
              norm(rate.force - fd_force) / norm(rate.force),
              norm(rate.torque) > 0 ? norm(rate.torque - fd_torque) / norm(rate.torque) : 0.0);
  EXPECT_LT(norm(rate.force - fd_force), tol * norm(rate.force)) << what << ": analytic (" << rate.force.x << ", "
                                                                  << rate.force.y << ", " << rate.force.z << "), FD ("
                                                                  << fd_force.x << ", " << fd_force.y << ", " << fd_force.z << ")";
  EXPECT_LE(norm(rate.torque - fd_torque), tol * norm(rate.torque) + 1e-30) << what;
}

// Drag at Re ~ 0.5, 50, 500 (Schiller-Naumann) and 5000 (capped): the velocity turns and
// changes its size.
TEST(FluidRates, DragMatchesFiniteDifference) {
  const Fluid f = only(true, true, false);
  const double d = 1e-3;
  for (double speed : {5e-4, 0.05, 0.5, 5.0}) {
    const Path p{{0.6 * speed, -0.3 * speed, -0.74 * speed}, {2 * speed, 1.5 * speed, 0.5 * speed}, {-3 * speed, speed, 2 * speed}, {}, {}, {}};
    const double h = 1e-5;  // Re changes by ~1e-4 relative: far from the kink at 1000
    expect_rates_match(f, d, p, h, 1e-7, ("drag, |u| = " + std::to_string(speed)).c_str());
  }
}

TEST(FluidRates, StokesTorqueMatchesFiniteDifference) {
  const Fluid f = only(false, false, true);
  const Path p{{0.01, 0, 0}, {}, {}, {10, -20, 5}, {300, 100, -50}, {1000, 0, 20}};
  // The torque is linear in omega; the force part is zero here, so check the torque only.
  const FluidLoad rate = fluid_load_rate(f, 1e-3, p.u0, p.a, p.w0, p.alpha);
  const double h = 1e-5;
  const Vec3 fd = (fluid_load(f, 1e-3, {}, p.u(h), p.w(h)).torque - fluid_load(f, 1e-3, {}, p.u(-h), p.w(-h)).torque) / (2 * h);
  EXPECT_LT(norm(rate.torque - fd), 1e-8 * norm(rate.torque));
  EXPECT_EQ(rate.force, Vec3{});  // buoyancy is constant
}

TEST(FluidRates, SpinCorrectionsMatchFiniteDifference) {
  const double d = 1e-3;
  // Re ~ 50 between table points, Omega* ~ 0.3 (and u, omega both turning).
  const Path p{{0.04, 0.01, -0.028}, {0.3, -0.2, 0.4}, {1, 1, -1}, {20, -35, 10}, {400, 300, -200}, {0, 1e3, 0}};
  Fluid loth = only(false, true, true, SpinModel::loth);
  expect_rates_match(loth, d, p, 1e-6, 1e-6, "drag + loth lift");
  const Fluid lift_only = only(false, false, false, SpinModel::loth);
  expect_rates_match(lift_only, d, p, 1e-6, 1e-6, "loth lift alone");
  Fluid kk = only(false, true, true, SpinModel::kurose_komori);
  kk.eta = {{1, 100, 500}, {0.2, 0.4, 0.5}, {1.0, 2.0, 2.5}, {0.5, 0.7, 0.6}};
  expect_rates_match(kk, d, p, 1e-6, 1e-6, "kurose-komori, Omega* < 0.5");
  Fluid kk_lift = kk;
  kk_lift.drag = false;
  expect_rates_match(kk_lift, d, p, 1e-6, 1e-6, "kurose-komori lift alone");
  // Omega* held at 0.5: only the Re dependence of eta and the drag remain.
  Path fast = p;
  fast.w0 = {200, -350, 100};
  expect_rates_match(kk, d, fast, 1e-6, 1e-6, "kurose-komori, Omega* > 0.5");
  // Re above 1000 with the lift: C_D capped, eta held at the last point.
  Path quick = p;
  quick.u0 = {2.0, 0.5, -1.4};
  quick.w0 = {200, -350, 100};
  expect_rates_match(loth, d, quick, 1e-6, 1e-6, "loth lift, Re > 1000");
  expect_rates_match(kk, d, quick, 1e-6, 1e-6, "kurose-komori, Re > 1000");
}

TEST(FluidRates, DragRateAtRestIsTheStokesLimit) {
  const Fluid f = only(false, true, false);
  const double d = 1e-3, area = M_PI * d * d / 4;
  const Vec3 a{0, 0, -3};
  const FluidLoad rate = fluid_load_rate(f, d, {}, a, {}, {});
  const Vec3 expect = -(0.5 * kRhoF * area * kNu / d * 24) * a;  // 3 pi mu d a
  EXPECT_NEAR(norm(rate.force - expect), 0, 1e-12 * norm(expect));
  EXPECT_NEAR(norm(expect), 3 * M_PI * kRhoF * kNu * d * 3, 1e-15);
}

// The slope the block-step corrector moves the load along (FluidSlope) is the load's
// derivative: against central differences of fluid_load along a velocity and a spin change,
// below and above the cap, hindered and at rest; its relaxation time at the evaluated speed is
// drag_relaxation_time's, and a lift model is not given a slope.
TEST(FluidSlope, IsTheLoadsDerivativeWithRespectToVelocityAndSpin) {
  const double d = 1e-3;
  Fluid hindered = water();
  hindered.hindered = true;
  const Crowding crowd{0.2, 5.0, 3.1};
  const Vec3 du{0.3, -0.7, 0.2}, dw{40, 10, -25};
  for (const Fluid& f : {water(), hindered})
    for (double speed : {0.0, 5e-4, 0.05, 0.3, 5.0}) {  // hindered, 0.3 m/s is Re 600, 5 m/s capped
      const Vec3 u{0.6 * speed, -0.3 * speed, -0.74 * speed}, w{30, -10, 5};
      const Crowding c = f.hindered ? crowd : Crowding{};
      FluidSlope slope;
      fluid_load_with_rate(f, d, {0, 0, -9.81}, u, {}, w, {}, c, &slope);
      ASSERT_TRUE(slope.exact);
      const double h = speed > 0 ? 1e-6 * speed : 1e-9;
      const FluidLoad up = fluid_load(f, d, {0, 0, -9.81}, u + h * du, w + h * dw, c);
      const FluidLoad down = fluid_load(f, d, {0, 0, -9.81}, u - h * du, w - h * dw, c);
      const Vec3 force = (up.force - down.force) / (2 * h), torque = (up.torque - down.torque) / (2 * h);
      const std::string at = std::string(f.hindered ? "hindered" : "lone") + ", |u| = " + std::to_string(speed);
      // At rest the drag's Re^0.687 term is not differentiable: its slope there is the Stokes drag's.
      EXPECT_LT(norm(slope.force_change(du) - force), (speed > 0 ? 1e-6 : 1e-2) * norm(force)) << at;
      EXPECT_LT(norm(slope.torque_change(dw) - torque), 1e-7 * norm(torque)) << at;
      const double m = 3e-6, q = norm(u);
      EXPECT_NEAR(slope.relaxation_time(m, q), drag_relaxation_time(f, d, m, q, c), 1e-12 * drag_relaxation_time(f, d, m, q, c)) << at;
      if (speed > 0)  // moved along the slope to 1 % more speed: the law's value to second order
        EXPECT_NEAR(slope.relaxation_time(m, 1.01 * q), drag_relaxation_time(f, d, m, 1.01 * q, c),
                    1e-3 * drag_relaxation_time(f, d, m, q, c)) << at;
    }
  FluidSlope slope;
  fluid_load_with_rate(only(false, true, true, SpinModel::loth), d, {}, {0.01, 0, 0}, {}, {0, 10, 0}, {}, {}, &slope);
  EXPECT_FALSE(slope.exact);
}

}  // namespace
}  // namespace tsubu
