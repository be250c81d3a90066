// Single quartz spheres released from rest in still water, through the full engine (force
// field with the fluid, velocity Verlet): the terminal speed, the transient with added mass
// against an independent RK4 solution, and the Stokes-torque decay of a spin
// (docs/engine.md, "Fluid forces").
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/build_world.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

constexpr double kRhoP = 2650, kRhoF = 1000, kNu = 1e-6, kG = 9.81, kCm = 0.5;

// The reference physics, written out here independently of src/tsubu/fluid.
double cd(double re) { return re <= 1000 ? 24 / re * (1 + 0.15 * std::pow(re, 0.687)) : 0.44; }

struct Sphere {
  double d, m, volume, area;
  explicit Sphere(double diameter)
      : d(diameter), m(kRhoP * M_PI * diameter * diameter * diameter / 6), volume(M_PI * diameter * diameter * diameter / 6),
        area(M_PI * diameter * diameter / 4) {}
  double drag(double v) const { return v > 0 ? 0.5 * cd(v * d / kNu) * kRhoF * area * v * v : 0.0; }
  double weight() const { return (m - kRhoF * volume) * kG; }
  // dv/dt of the downward speed, the added mass as inertia.
  double accel(double v) const { return (weight() - drag(v)) / (m + kCm * kRhoF * volume); }
};

// Solves drag(u) = (m - rho_f V) g by bisection (drag grows with u).
double terminal_speed(const Sphere& s) {
  double lo = 0, hi = 100;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (s.drag(mid) < s.weight() ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Classical RK4 for dv/dt = accel(v), from v(0) = 0.
struct Rk4 {
  const Sphere& s;
  double v = 0, t = 0;
  void advance_to(double t_end, double h) {
    while (t < t_end - 1e-15) {
      const double step = std::min(h, t_end - t);
      const double k1 = s.accel(v), k2 = s.accel(v + 0.5 * step * k1), k3 = s.accel(v + 0.5 * step * k2),
                   k4 = s.accel(v + step * k3);
      v += step / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      t += step;
    }
  }
};

testing::Bed water_world(double dt, const Vec3& gravity) {
  testing::Bed b = testing::make_world({"quartz", kRhoP, 1e9, 0.17}, testing::spec_of("hertz_tsuji", "none", 1.0), dt, gravity);
  b.model.fluid.enabled = true;
  b.model.fluid.density = kRhoF;
  b.model.fluid.viscosity = kNu;
  return b;
}

struct SettlingResult {
  double terminal, engine_final;  // m/s
  double worst_transient;         // max |v - v_rk4| / v_terminal over every step
  double worst_relative;          // max |v - v_rk4| / v_rk4 over every step
};

// Releases one sphere from rest; dt and duration in units of the time scale
// u_t / g', g' = (m - rho_f V) g / (m + C_M rho_f V) (the Stokes relaxation time for small Re).
SettlingResult settle(double d, Integrator integrator, double steps_per_scale = 400, double scales = 12) {
  const Sphere s(d);
  const double ut = terminal_speed(s);
  const double scale = ut / s.accel(0);
  const double dt = scale / steps_per_scale;
  auto [w, model] = water_world(dt, {0, 0, -kG});
  w.particles.add(0, 0, d, kRhoP, {0, 0, 0}, {});
  ForceField f(model);
  f.compute(w);
  Rk4 ref{s};
  SettlingResult r{ut, 0, 0, 0};
  const auto steps = static_cast<std::int64_t>(std::llround(scales * steps_per_scale));
  for (std::int64_t k = 0; k < steps; ++k) {
    advance(integrator, w, testing::evaluation(f, w));
    ref.advance_to(w.time, dt / 8);
    const double v = -w.particles.velocity[0].z;
    r.worst_transient = std::max(r.worst_transient, std::abs(v - ref.v) / ut);
    r.worst_relative = std::max(r.worst_relative, std::abs(v - ref.v) / ref.v);
  }
  r.engine_final = -w.particles.velocity[0].z;
  return r;
}

class Settling : public ::testing::TestWithParam<double> {};

TEST_P(Settling, ReachesTerminalSpeedAndFollowsTheTransient) {
  const double d = GetParam();
  const SettlingResult r = settle(d, Integrator::velocity_verlet);
  const double err = std::abs(r.engine_final - r.terminal) / r.terminal;
  std::printf("d = %g m: terminal %.6f m/s (Re %.4g), engine %.6f m/s, error %.2e; transient vs RK4: max %.2e of u_t, "
              "max %.2e relative\n",
              d, r.terminal, r.terminal * d / kNu, r.engine_final, err, r.worst_transient, r.worst_relative);
  EXPECT_LT(err, 0.005);
  EXPECT_LT(r.worst_transient, 0.005);
  EXPECT_LT(r.worst_relative, 0.005);
}

INSTANTIATE_TEST_SUITE_P(Quartz, Settling, ::testing::Values(1e-4, 1e-3, 1e-2),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return info.param == 1e-4 ? std::string("d0_1mm") : info.param == 1e-3 ? "d1mm" : "d1cm";
                         });

// The terminal speed is a fixed point of either integrator (F(u_t) = 0), so symplectic Euler
// reaches it too.
TEST(SettlingSymplecticEuler, ReachesTerminalSpeed) {
  const SettlingResult r = settle(1e-3, Integrator::symplectic_euler);
  EXPECT_LT(std::abs(r.engine_final - r.terminal) / r.terminal, 0.005);
  EXPECT_LT(r.worst_transient, 0.01);
}

// The smooth sphere and Rubey's natural grain: ~0.70 vs ~0.33 m/s for 1 cm quartz.
TEST(SettlingReference, SmoothSphereAgainstRubey) {
  const double ut = terminal_speed(Sphere(0.01));
  EXPECT_NEAR(ut, 0.70, 0.01);
  EXPECT_NEAR(rubey_speed(kRhoP, kRhoF, kNu, 0.01, kG), 0.33, 0.005);
}

// A spinning sphere at rest decays as omega0 exp(-k t), k = pi rho_f nu d^3 / I. Velocity
// Verlet evaluates the torque at the spin extrapolated to the step's end, so the rate is
// right to second order in k dt.
TEST(SpinDecay, FollowsTheStokesTorque) {
  const double d = 1e-3;
  const Sphere s(d);
  const double inertia = s.m * d * d / 10;
  const double k = M_PI * kRhoF * kNu * d * d * d / inertia;
  const double dt = 1e-3 / k;
  auto [w, model] = water_world(dt, {});
  w.particles.add(0, 0, d, kRhoP, {0, 0, 0}, {});
  const Vec3 w0{30, -40, 120};
  w.particles.omega[0] = w0;
  ForceField f(model);
  f.compute(w);
  double worst = 0;
  for (int n = 0; n < 3000; ++n) {
    velocity_verlet_step(w, testing::evaluation(f, w));
    const Vec3 expect = std::exp(-k * w.time) * w0;
    worst = std::max(worst, norm(w.particles.omega[0] - expect) / norm(expect));
  }
  const double rate = std::log(norm(w0) / norm(w.particles.omega[0])) / w.time;
  std::printf("spin decay d = 1 mm: k = %.6f 1/s, measured %.6f 1/s (%.2e), worst |omega - exact|/|exact| %.2e over 3/k\n",
              k, rate, std::abs(rate - k) / k, worst);
  EXPECT_LT(std::abs(rate - k) / k, 0.005);
  EXPECT_LT(worst, 0.005);
  EXPECT_EQ(w.particles.velocity[0], Vec3{});  // no lift at rest, no drag without motion
}

// A 1 mm quartz grain released from rest in water, position and speed after 0.04 s: velocity
// Verlet converges at second order (error ratio 4 per halving of dt). With the fluid's forces
// at the half-step velocity it was first order (3.3e-4, 1.7e-4, 8.3e-5 relative at dt = 4e-5,
// 2e-5, 1e-5).
TEST(SettlingVelocityVerlet, SecondOrderInDt) {
  auto speed_after = [](double dt) {
    auto [w, model] = water_world(dt, {0, 0, -kG});
    w.particles.add(0, 0, 1e-3, kRhoP, {0, 0, 0}, {});
    ForceField f(model);
    f.compute(w);
    for (int n = 0; n < std::lround(0.04 / dt); ++n) velocity_verlet_step(w, testing::evaluation(f, w));
    return -w.particles.velocity[0].z;
  };
  const double exact = speed_after(2.5e-6);
  double last = 0;
  for (double dt : {4e-5, 2e-5, 1e-5}) {
    const double e = std::abs(speed_after(dt) - exact) / exact;
    std::printf("velocity Verlet in water, dt = %g s: relative speed error %.2e\n", dt, e);
    if (last > 0) {
      EXPECT_GT(last / e, 3.5);
      EXPECT_LT(last / e, 4.5);
    }
    last = e;
  }
}

// Without [fluid] nothing changes: the translational mass is the mass, no fluid force.
TEST(NoFluid, FreeFallUnchanged) {
  auto [w, model] = testing::make_world({"quartz", kRhoP, 1e9, 0.17}, testing::spec_of("hertz_tsuji", "none", 1.0), 1e-3,
                                {0, 0, -kG});
  w.particles.add(0, 0, 1e-3, kRhoP, {0, 0, 0}, {});
  ForceField f(model);
  f.compute(w);
  for (int n = 0; n < 100; ++n) velocity_verlet_step(w, testing::evaluation(f, w));
  EXPECT_EQ(w.particles.translational_mass[0], w.particles.mass[0]);
  EXPECT_NEAR(w.particles.velocity[0].z, -kG * 0.1, 1e-12);
}

// The example scenarios load with their [fluid] section and settle to the terminal speed.
TEST(SettlingExamples, OneMillimetreScenarioReachesTerminalSpeed) {
  const Scenario sc = load_scenario(std::string(TSUBU_SOURCE_DIR) + "/examples/settling/quartz_1mm.toml");
  ASSERT_TRUE(sc.fluid.enabled);
  EXPECT_EQ(sc.fluid.density, kRhoF);
  EXPECT_EQ(sc.fluid.viscosity, kNu);
  World w = build_world(sc);
  ASSERT_EQ(w.particles.size(), 1u);
  const Model model = build_model(sc);
  ForceField f(model);
  f.compute(w);
  EXPECT_NEAR(w.particles.translational_mass[0], Sphere(1e-3).m + kCm * kRhoF * Sphere(1e-3).volume, 1e-15);
  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  for (std::int64_t k = 0; k < steps; ++k) advance(sc.integrator, w, testing::evaluation(f, w));
  const double ut = terminal_speed(Sphere(1e-3));
  EXPECT_NEAR(-w.particles.velocity[0].z, ut, 0.005 * ut);
}

// The fluid forces are per particle, so 1 and 2 threads still give the same bits (a
// collapsing lattice in water, with spin lift).
TEST(FluidThreads, OneAndTwoThreadsGiveIdenticalBits) {
  auto run = [](int threads) {
    const Scenario sc = load_scenario(std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/lattice_threads.toml",
                                      {"fluid.density=1000", "fluid.kinematic_viscosity=1e-6", "fluid.lift=\"loth\""});
    omp_set_num_threads(threads);
    World w = build_world(sc);
    const Model model = build_model(sc);
    EXPECT_TRUE(model.fluid.enabled);
    ForceField f(model);
    f.compute(w);
    for (int k = 0; k < 100; ++k) advance(sc.integrator, w, testing::evaluation(f, w));
    omp_set_num_threads(1);
    return w;
  };
  const World one = run(1), two = run(2);
  auto same = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
  };
  EXPECT_TRUE(same(one.particles.position, two.particles.position));
  EXPECT_TRUE(same(one.particles.velocity, two.particles.velocity));
  EXPECT_TRUE(same(one.particles.omega, two.particles.omega));
}

}  // namespace
}  // namespace tsubu
