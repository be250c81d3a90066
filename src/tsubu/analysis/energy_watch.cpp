#include "tsubu/analysis/energy_watch.hpp"

#include <cmath>
#include <sstream>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/core/error.hpp"

namespace tsubu {

void require_finite_energies(const World& world, const Vec3& gravity, double elastic_energy) {
  const Particles& p = world.particles;
  std::ostringstream msg;
  msg << "step " << world.step << ", t = " << world.time << " s: ";
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double translational = p.translational_energy(i), rotational = p.rotational_energy(i);
    if (std::isfinite(translational) && std::isfinite(rotational)) continue;
    const Vec3 &v = p.velocity[i], &w = p.omega[i];
    msg << "the kinetic energy of particle id " << p.id[i] << " is not finite (translational " << translational
        << " J at velocity (" << v.x << ", " << v.y << ", " << v.z << ") m/s, rotational " << rotational
        << " J at spin (" << w.x << ", " << w.y << ", " << w.z << ") rad/s; diameter " << 2 * p.radius[i] << " m)";
    throw NumericalError(msg.str());
  }
  const Energies e = energies(world, gravity);
  if (std::isfinite(e.kinetic_translational + e.kinetic_rotational + e.potential_gravity + elastic_energy)) return;
  msg << "the energies are not finite (kinetic " << e.kinetic_translational << " J, rotational " << e.kinetic_rotational
      << " J, gravitational " << e.potential_gravity << " J, elastic " << elastic_energy << " J)";
  throw NumericalError(msg.str());
}

EnergyWatch::EnergyWatch(const World& world, const Model& model, double limit) : limit_(limit), gravity_(model.gravity) {
  on_ = limit > 0 && !model.fluid.enabled;
  for (const Wall& w : world.walls)
    if (!w.motion.empty() || w.surface_moves()) on_ = false;
  for (int k = 0; k < 3; ++k)
    if (world.domain.periodic[k] && gravity_[k] != 0) on_ = false;
}

void EnergyWatch::observe(const World& world, double elastic_energy) {
  require_finite_energies(world, gravity_, elastic_energy);
  if (!on_) return;
  const Energies e = energies(world, gravity_);
  const double active = e.kinetic_translational + e.kinetic_rotational + elastic_energy;
  const double total = active + e.potential_gravity;
  if (!state_.started) {
    state_ = {true, total, active};
    return;
  }
  state_.active_max = std::max(state_.active_max, active);
  const double growth = total - state_.reference;
  if (growth > 0 && growth > limit_ * state_.active_max) {
    // The particle with the most kinetic energy: where the spurious energy went.
    const Particles& p = world.particles;
    std::size_t fastest = 0;
    double most = -1;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double k = p.mass[i] * norm2(p.velocity[i]) + p.inertia[i] * norm2(p.omega[i]);
      if (k > most) most = k, fastest = i;
    }
    std::ostringstream msg;
    msg << "step " << world.step << ", t = " << world.time << " s: the total energy grew by " << growth
        << " J (from " << state_.reference << " J) although nothing does work on the particles; the largest kinetic + "
        << "elastic energy so far is " << state_.active_max << " J (simulation.energy_growth_limit = " << limit_ << ")";
    if (most >= 0)
      msg << "; particle id " << p.id[fastest] << " has the most kinetic energy, " << 0.5 * most << " J, with "
          << p.contact_count[fastest] << " contacts";
    msg << "; the time step " << world.dt << " s is probably too large for the contact stiffness: try dt/4";
    throw NumericalError(msg.str());
  }
}

}  // namespace tsubu
