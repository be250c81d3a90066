#include "tsubu/analysis/measures.hpp"

#include <algorithm>
#include <cmath>

#include "tsubu/core/exact_sum.hpp"

namespace tsubu {

Energies energies(const World& w, const Vec3& g) {
  const Particles& p = w.particles;
  ExactSum translational, rotational, potential;
  for (std::size_t i = 0; i < p.size(); ++i) {
    translational += p.translational_energy(i);
    rotational += p.rotational_energy(i);
    potential += -(p.mass[i] * dot(g, p.position[i]));
  }
  return {translational.value(), rotational.value(), potential.value()};
}

double sphere_slab_volume(double z0, double r, double a, double b) {
  const double lo = std::max(a - z0, -r), hi = std::min(b - z0, r);
  if (hi <= lo) return 0;
  auto primitive = [r](double z) { return M_PI * (r * r * z - z * z * z / 3); };  // ∫ pi (r^2 - z^2) dz
  return primitive(hi) - primitive(lo);
}

Packing packing_of(const World& w) { return {w.domain, w.particles.position, w.particles.radius}; }

std::vector<int> pair_contact_counts(const World& w) {
  std::vector<int> z(w.particles.size(), 0);
  for (const Contact& c : w.contacts.pairs())
    if (c.touching) ++z[c.i], ++z[c.j];
  return z;
}

double solid_fraction(const World& w, double a, double b) { return solid_fraction(packing_of(w), a, b); }

double coordination(const World& w, double a, double b, bool without_rattlers) {
  const Coordination c = coordination_numbers(w.particles.position, pair_contact_counts(w), a, b);
  return without_rattlers ? c.without_rattlers_2 : c.all;
}

}  // namespace tsubu
