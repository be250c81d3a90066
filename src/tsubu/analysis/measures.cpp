#include "tsubu/analysis/measures.hpp"

#include <algorithm>
#include <cmath>

namespace tsubu {

Energies energies(const World& w) {
  const Particles& p = w.particles;
  Energies e;
  for (std::size_t i = 0; i < p.size(); ++i) {
    e.kinetic_translational += 0.5 * p.mass[i] * norm2(p.velocity[i]);
    e.kinetic_rotational += 0.5 * p.inertia[i] * norm2(p.omega[i]);
    e.potential_gravity -= p.mass[i] * dot(w.gravity, p.position[i]);
  }
  return e;
}

double sphere_slab_volume(double z0, double r, double a, double b) {
  const double lo = std::max(a - z0, -r), hi = std::min(b - z0, r);
  if (hi <= lo) return 0;
  auto primitive = [r](double z) { return M_PI * (r * r * z - z * z * z / 3); };  // ∫ pi (r^2 - z^2) dz
  return primitive(hi) - primitive(lo);
}

double solid_fraction(const World& w, double a, double b) {
  const Particles& p = w.particles;
  double solid = 0;
  for (std::size_t i = 0; i < p.size(); ++i) solid += sphere_slab_volume(p.position[i].z, p.radius[i], a, b);
  return solid / (w.domain.length(0) * w.domain.length(1) * (b - a));
}

double coordination(const World& w, double a, double b, bool without_rattlers) {
  const Particles& p = w.particles;
  std::vector<int> z(p.size(), 0);
  for (const Contact& c : w.pair_contacts)
    if (c.touching) ++z[c.i], ++z[c.j];
  long contacts = 0, particles = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double h = p.position[i].z;
    if (h <= a || h >= b || (without_rattlers && z[i] < 2)) continue;
    contacts += z[i];
    ++particles;
  }
  return particles ? static_cast<double>(contacts) / static_cast<double>(particles) : 0.0;
}

}  // namespace tsubu
