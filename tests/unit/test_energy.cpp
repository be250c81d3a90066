// Isolated elastic bounce: velocity Verlet with an undamped Hertz contact conserves the
// total energy (kinetic + gravitational + elastic) over 100 bounces.
#include <gtest/gtest.h>

#include <cmath>

#include "tsubu/analysis/measures.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

struct BounceResult {
  int bounces = 0;
  double worst_apex = 0;    // largest |E - E0| / E0 at the apexes (out of contact)
  double worst_anytime = 0; // largest |E - E0| / E0 at any step
};

// Hertz contact time of a sphere of mass m, radius r hitting a plane at speed v
// (E* of the pair): t_c = 2.868 (m^2 / (r E*^2 v))^{1/5}.
double hertz_contact_time(double m, double r, double e_star, double v) {
  return 2.868 * std::pow(m * m / (r * e_star * e_star * v), 0.2);
}

// A 2 mm glass sphere dropped from 10 um above the floor (impact 1.4 cm/s), so that a
// bounce takes few steps outside the contact.
BounceResult bounce(double dt, int n_bounces) {
  const Material glass{"glass", 2500, 1e9, 0.25};
  auto [w, model] = testing::make_world(glass, testing::spec_of("hertz_tsuji", "none", 1.0), dt, {0, 0, -9.81});
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0});
  const double d = 2e-3, r = 1e-3, h = 1e-5;
  w.particles.add(0, 0, d, glass.density, {0, 0, r + h}, {});
  ForceField f(model);
  f.compute(w);
  const Particles& p = w.particles;
  const double m = p.mass[0], e0 = m * 9.81 * h;
  auto energy = [&] {
    const Energies e = energies(w, model.gravity);
    return e.kinetic_translational + e.kinetic_rotational + e.potential_gravity - m * 9.81 * r + f.totals(w).elastic_energy;
  };
  BounceResult out;
  bool in_contact = false;
  double previous_vz = 0;
  while (out.bounces < n_bounces) {
    velocity_verlet_step(w, testing::evaluation(f, w));
    const double error = std::abs(energy() - e0) / e0;
    out.worst_anytime = std::max(out.worst_anytime, error);
    const bool touching = f.totals(w).contacts > 0;
    if (in_contact && !touching) ++out.bounces;
    in_contact = touching;
    if (previous_vz > 0 && p.velocity[0].z <= 0) out.worst_apex = std::max(out.worst_apex, error);
    previous_vz = p.velocity[0].z;
  }
  return out;
}

// Out of contact the energy must come back to E0 (no drift): 1e-6 over 100 bounces. Inside
// a contact velocity Verlet's energy oscillates by about (omega dt)^2/4 of the contact
// energy (harmonic estimate, omega = pi/t_c), and that bounds it.
TEST(ElasticBounce, EnergyConservedOver100Bounces) {
  const double m = 2500 * M_PI / 6 * 8e-9, e_star = 1e9 / (2 * (1 - 0.25 * 0.25));
  const double t_c = hertz_contact_time(m, 1e-3, e_star, std::sqrt(2 * 9.81 * 1e-5));
  const double dt = t_c / 400;  // measured drift: 4e-5, 4e-6, 3e-7, 8e-8 at t_c/100..800
  const BounceResult r = bounce(dt, 100);
  EXPECT_EQ(r.bounces, 100);
  EXPECT_LT(r.worst_apex, 1e-6);
  EXPECT_LT(r.worst_anytime, std::pow(M_PI * dt / t_c, 2) / 4);
}

}  // namespace
}  // namespace tsubu
