// Rolling resistance (docs/contact-laws.md, "Rolling resistance"): a sphere rolling on a
// wall under model CDT decelerates and stops as the analytic solution says; under model EPSD
// a sphere on an incline stays put below the model's limit and rolls away above it (both
// with velocity Verlet and with block steps); the torques on a pair are equal and opposite
// and vanish without relative rotation; the history's swap rule holds; the contact network
// carries the rolling spring.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <vector>

#include "tsubu/contact/law.hpp"
#include "tsubu/io/contact_network.hpp"
#include "tsubu/io/vtk.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu_process.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

using testing::Bed;
using testing::make_world;
using testing::spec_of;

const Material kGlass{"glass", 2500, 1e8, 0.2};
constexpr double kDiameter = 0.01, kRadius = 0.005, kG = 9.81;

ContactSpec rolling_spec(const char* model, double mu_r, double eta_r = 0) {
  ContactSpec s = spec_of("hertz_tsuji", "mindlin", 0.5, 0.5);
  s.rolling = model;
  s.values.set("rolling_friction", mu_r);
  if (eta_r > 0) s.values.set("rolling_damping", eta_r);
  return s;
}

// One sphere resting on the floor z = 0 at the static overlap of Hertz under gravity
// g (0, 0, -1) tilted by theta about y, with velocity v and spin w.
Bed sphere_on_floor(const ContactSpec& spec, double theta, const Vec3& v, const Vec3& w, double dt) {
  Bed b = make_world(kGlass, spec, dt, {kG * std::sin(theta), 0, -kG * std::cos(theta)});
  b.world.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0});
  const double e_star = effective_modulus(kGlass, kGlass);
  const double mass = kGlass.density * M_PI / 6 * std::pow(kDiameter, 3);
  const double load = mass * kG * std::cos(theta);
  const double overlap = std::pow(3 * load / (4 * e_star * std::sqrt(kRadius)), 2.0 / 3.0);  // F = 4/3 E* sqrt(R) delta^{3/2}
  b.world.particles.add(0, 0, kDiameter, kGlass.density, {0, 0, kRadius - overlap}, v);
  b.world.particles.omega[0] = w;
  return b;
}

// Runs the bed with `integrator` for `steps` steps of its dt, calling each(t, world) after
// every one (block steps: every block time dt, when every grain is at t).
template <class Each>
void run_bed(Bed b, Integrator integrator, int steps, Each&& each) {
  const double dt = b.world.dt;
  Simulation sim(std::move(b.world), std::move(b.model), integrator, BlockStepRules{});
  sim.start();
  for (int k = 1; k <= steps; ++k) {
    sim.advance_to(k);
    each(k * dt, sim.world());
  }
}

// Velocity Verlet at 20 us (1/100 of the contact's period at rest), block steps at dt = 1 ms
// (their contact rule sets the steps).
struct Stepping {
  Integrator integrator;
  double dt;
};
constexpr Stepping kSteppings[] = {{Integrator::velocity_verlet, 2e-5}, {Integrator::block_hermite, 1e-3}};

// Model CDT, a sphere rolling without slipping at v0 along x. The wall's torque M = mu_r R
// m g against the spin and the friction force F at the contact (which keeps the rolling
// without slip: mu >= 5 mu_r / 7 is needed, here 0.5) give m dv/dt = F and
// I dw/dt = -R F - M with v = w R, I = 2/5 m R^2: dv/dt = -M / (R (m + I / R^2)) = -5/7
// mu_r g. It stops after v0^2 / (2 a) at t = v0 / a. The overlap shortens the friction's
// lever arm to R - delta/2 (delta/R = 4e-4 here), which changes a by a part in 10^4; the
// tangential spring's oscillation, set off as the torque starts, is damped within a few ms.
// The stop is found between two steps by the line through their velocities (exact for a
// constant deceleration), so that block steps, seen every 1 ms, place it as finely.
TEST(RollingResistance, ConstantTorqueStopsASphereAtTheAnalyticRateAndDistance) {
  const double mu_r = 0.05, v0 = 0.1;
  const double a = 5.0 / 7.0 * mu_r * kG;
  const double stop_time = v0 / a, stop_distance = v0 * v0 / (2 * a);
  for (const auto [integrator, dt] : kSteppings) {
    const char* name = integrator_name(integrator);
    // v(t) on [0.05, 0.25] s, fitted by least squares to a line: its slope is -a.
    double st = 0, sv = 0, stt = 0, stv = 0, n = 0;
    double stopped_at = -1, stopped_after = 0, v_before = v0, x_before = 0, v_end = 0;
    const int steps = static_cast<int>(1.2 * stop_time / dt);
    run_bed(sphere_on_floor(rolling_spec("cdt", mu_r), 0, {v0, 0, 0}, {0, v0 / kRadius, 0}, dt), integrator, steps,
            [&](double t, const World& w) {
              const double v = w.particles.velocity[0].x, x = w.particles.position[0].x;
              if (t >= 0.05 && t <= 0.25) st += t, sv += v, stt += t * t, stv += t * v, n += 1;
              if (stopped_at < 0 && v <= 0) {
                const double since = dt * v_before / (v_before - v);  // the stop, after the step before
                stopped_at = t - dt + since, stopped_after = x_before + 0.5 * v_before * since;
              }
              v_before = v, x_before = x, v_end = v;
            });
    const double slope = (n * stv - st * sv) / (n * stt - st * st);
    std::printf("%s: deceleration %.6f m/s^2 (analytic %.6f), stopped after %.6f m at %.5f s (analytic %.6f m, %.5f s), "
                "at the end v = %.3g m/s\n",
                name, -slope, a, stopped_after, stopped_at, stop_distance, stop_time, v_end);
    EXPECT_NEAR(-slope / a, 1.0, 2e-3) << name;
    EXPECT_NEAR(stopped_after / stop_distance, 1.0, 2e-3) << name;
    EXPECT_NEAR(stopped_at, stop_time, 2e-3 * stop_time) << name;
    // After the stop the torque flips with the spin (the model's known chatter): the sphere
    // stays within a step's deceleration of rest (block steps: of their 32 us steps there).
    EXPECT_LT(std::abs(v_end), 10 * a * 2e-5 * (integrator == Integrator::block_hermite ? 1.6 : 1.0)) << name;
  }
}

// Model EPSD on an incline of slope tan(theta), from rest. The sphere holds while the
// wall's friction torque R m g sin(theta) stays below the limit mu_r R m g cos(theta), that
// is tan(theta) < mu_r; it then rests after turning by the rolling spring's deflection
// M/k_r (k_r = 2.25 k_n mu_r^2 R^2) and creeps no further. (The load comes on at once: the
// spring, damped at eta_r = 0.3, overshoots the static torque by up to 37 %, which at
// tan(theta) = 0.8 mu_r passes the cap and slips the spring once, a little: the sphere
// rests at 1.26 R M/k_r, within the bound 1.5 R M/k_r below.) Above the limit the torque
// is fully mobilised, the constant mu_r R m g cos(theta), and the sphere rolls down at
// a = 5/7 g (sin(theta) - mu_r cos(theta)) (as CDT's deceleration above).
TEST(RollingResistance, ElasticPlasticSpringHoldsASphereBelowTheLimitAndLetsItRollAbove) {
  const double mu_r = 0.1;
  const double mass = kGlass.density * M_PI / 6 * std::pow(kDiameter, 3);
  for (const auto [integrator, dt] : kSteppings)
  for (double slope : {0.8 * mu_r, 1.2 * mu_r}) {
    const char* name = integrator_name(integrator);
    const double theta = std::atan(slope);
    Vec3 at_half, x;
    double v_half = 0, v_end = 0;
    const int steps = static_cast<int>(std::lround(0.3 / dt));
    run_bed(sphere_on_floor(rolling_spec("epsd", mu_r, 0.3), theta, {}, {}, dt), integrator, steps,
            [&](double t, const World& w) {
              if (std::lround(t / dt) == steps / 2) at_half = w.particles.position[0], v_half = w.particles.velocity[0].x;
              x = w.particles.position[0], v_end = w.particles.velocity[0].x;
            });
    if (slope < mu_r) {
      // The spring's deflection: k_n = 2 E* sqrt(R delta) at the static overlap.
      const double load = mass * kG * std::cos(theta);
      const double e_star = effective_modulus(kGlass, kGlass);
      const double overlap = std::pow(3 * load / (4 * e_star * std::sqrt(kRadius)), 2.0 / 3.0);
      const double k_r = 2.25 * 2 * e_star * std::sqrt(kRadius * overlap) * mu_r * mu_r * kRadius * kRadius;
      const double turn = kRadius * mass * kG * std::sin(theta) / k_r;
      std::printf("%s, tan(theta) = %.3f: held, moved %.3e m (the spring's deflection R M/k_r = %.3e m), %.3e m in the last "
                  "0.15 s\n",
                  name, slope, x.x, kRadius * turn, x.x - at_half.x);
      EXPECT_LT(std::abs(x.x), 1.5 * kRadius * turn) << name << ": more than the elastic deflection";
      EXPECT_LT(std::abs(x.x - at_half.x), 1e-3 * kRadius * turn) << name << ": creeps";
    } else {
      const double a = 5.0 / 7.0 * kG * (std::sin(theta) - mu_r * std::cos(theta));
      const double rate = (v_end - v_half) / (0.15);
      std::printf("%s, tan(theta) = %.3f: rolls, acceleration %.5f m/s^2 (analytic %.5f), %.3e m in 0.3 s\n", name, slope, rate,
                  a, x.x);
      EXPECT_NEAR(rate / a, 1.0, 1e-2) << name;
      EXPECT_GT(x.x, 0.4 * a * 0.3 * 0.3) << name;
    }
  }
}

// Two spheres touching along x, each law (no tangential force, so that the torques are the
// rolling model's alone): spins that differ in the contact plane give torques equal and
// opposite to the bit, of mu_r R* |F_n| for CDT; equal spins, or spins that differ only
// about the normal (twist), give none. The pair gives the same bits whichever particle has
// the smaller id (the history's swap rule). Here w_r = (0, 5, -1): the torque is along -w_r.
struct Pair2 {
  Vec3 torque_a, torque_b, omega_a, omega_b;
};
Pair2 touching_pair(const char* model, const Vec3& wa, const Vec3& wb, bool swap_ids, int steps) {
  ContactSpec spec = rolling_spec(model, 0.1, std::string_view(model) == "epsd" ? 0.3 : 0);
  spec.tangential = "none";
  Bed b = make_world(kGlass, spec, 1e-6);
  auto& [w, law] = b;
  w.particles.add(swap_ids ? 1 : 0, 0, kDiameter, kGlass.density, {0, 0, 0}, {});
  w.particles.add(swap_ids ? 0 : 1, 0, kDiameter, kGlass.density, {kDiameter - 1e-5, 0, 0}, {});
  w.particles.omega[0] = wa, w.particles.omega[1] = wb;
  ForceField f(law);
  if (steps == 0) f.compute(w);
  for (int k = 0; k < steps; ++k) velocity_verlet_step(w, testing::evaluation(f, w));
  const Particles& p = w.particles;
  return {p.torque[0], p.torque[1], p.omega[0], p.omega[1]};
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(RollingResistance, TorquesAreEqualAndOppositeAndVanishWithoutRelativeRolling) {
  for (const char* model : {"cdt", "epsd"}) {
    const Pair2 r = touching_pair(model, {0, 3, -1}, {0, -2, 0}, false, 0);
    EXPECT_EQ(r.torque_a, -r.torque_b) << model;  // to the bit (but for the sign of a zero)
    EXPECT_EQ(r.torque_a.x, 0) << model << ": no torque about the normal (twist)";
    EXPECT_LT(r.torque_a.y, 0) << model << ": against the relative rolling";
    if (std::string_view(model) == "cdt") {
      // |F_n| = 4/3 E* sqrt(R*) delta^{3/2} (no dashpot: the spheres are at rest), R* = R/2.
      const double e_star = effective_modulus(kGlass, kGlass), r_eff = kRadius / 2;
      const double fn = 4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(1e-5, 1.5);
      EXPECT_NEAR(norm(r.torque_a), 0.1 * r_eff * fn, 1e-12 * r_eff * fn);
    }
    for (const auto& [wa, wb] : {std::pair<Vec3, Vec3>{{0, 2, 1}, {0, 2, 1}}, {{5, 0, 0}, {-5, 0, 0}}}) {
      const Pair2 none = touching_pair(model, wa, wb, false, 0);
      EXPECT_EQ(norm2(none.torque_a), 0) << model;
      EXPECT_EQ(norm2(none.torque_b), 0) << model;
    }
    // 200 steps with the history: the same bits seen from either particle.
    const Pair2 one = touching_pair(model, {0, 3, -1}, {0, -2, 0.5}, false, 200);
    const Pair2 other = touching_pair(model, {0, 3, -1}, {0, -2, 0.5}, true, 200);
    EXPECT_TRUE(same_bits(one.omega_a, other.omega_a) && same_bits(one.omega_b, other.omega_b)) << model;
    EXPECT_NE(one.omega_a.y, 3) << model << ": the torque acted";
  }
}

// A sphere held on an incline by model EPSD: at rest the rolling spring carries the whole
// torque of the friction force that holds it, R m g sin(theta) (to the overlap's share of the
// lever arm, delta/R = 4e-4), and the contact files list it, after the columns of a law that
// does not roll; a scenario without rolling resistance writes no such columns.
TEST(RollingResistance, TheContactNetworkCarriesTheRollingSpring) {
  const double mu_r = 0.1, dt = 2e-5, theta = std::atan(0.8 * mu_r);
  const double mass = kGlass.density * M_PI / 6 * std::pow(kDiameter, 3);
  testing::TempDir dir;
  for (const char* model : {"epsd", "none"}) {
    Bed b = sphere_on_floor(std::string_view(model) == "none" ? spec_of("hertz_tsuji", "mindlin", 0.5, 0.5)
                                                              : rolling_spec(model, mu_r, 0.3),
                            theta, {}, {}, dt);
    auto& [w, law] = b;
    ForceField f(law);
    for (int k = 0; k < 15000; ++k) velocity_verlet_step(w, testing::evaluation(f, w));
    const std::vector<NetworkContact> network = contact_network(w, f.touching_contacts(w));
    ASSERT_EQ(network.size(), 1u);
    const std::filesystem::path csv = dir.path() / (std::string(model) + ".csv");
    write_contacts_csv(csv.string(), network, w.time, f.resists_rolling());
    const std::string text = testing::slurp(csv);
    const std::string header = text.substr(0, text.find('\n'));
    const bool rolls = std::string_view(model) == "epsd";
    EXPECT_EQ(f.resists_rolling(), rolls);
    EXPECT_EQ(header.ends_with("normal_history1,mr_x[N m],mr_y[N m],mr_z[N m]"), rolls) << header;
    EXPECT_EQ(header.ends_with("normal_history1"), !rolls) << header;
    const std::filesystem::path vtp = dir.path() / (std::string(model) + ".vtp");
    write_contacts_vtp(vtp.string(), network, w.time, f.resists_rolling());
    EXPECT_EQ(testing::slurp(vtp).find("Name=\"rolling_spring\"") != std::string::npos, rolls);
    if (!rolls) continue;
    const Vec3 spring = network[0].history.rolling;
    const double held = kRadius * mass * kG * std::sin(theta);
    EXPECT_NEAR(norm(spring), held, 1e-3 * held);
    EXPECT_NEAR(spring.y, -held, 1e-3 * held) << "about -y, against the spin of a roll down the slope (+x)";
    // The row's last three numbers are the spring, written to the bit.
    std::vector<double> row;
    for (std::size_t at = text.find('\n') + 1; at < text.size() && text[at] != '\n';) {
      std::size_t used = 0;
      row.push_back(std::stod(text.substr(at), &used));
      at += used + (text[at + used] == ',');
    }
    ASSERT_EQ(row.size(), 25u);
    EXPECT_TRUE(same_bits({row[22], row[23], row[24]}, spring));
  }
}

}  // namespace
}  // namespace tsubu
