// Measurements on the current state: energies and packing statistics.
#pragma once
#include <vector>

#include "tsubu/analysis/deposit.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

struct Energies {
  double kinetic_translational = 0;  // J
  double kinetic_rotational = 0;     // J
  double potential_gravity = 0;      // J, -sum m g.x (zero at the origin)
};

// The energies of the particles of w under gravity g (m/s^2).
Energies energies(const World& w, const Vec3& g);

// Volume of the sphere (centre height z0, radius r) between the planes z = a and z = b.
double sphere_slab_volume(double z0, double r, double a, double b);

// The world's grains as a Packing (deposit.hpp), for the deposit measurements.
Packing packing_of(const World& w);

// Particle-particle contacts (touching pairs, walls excluded) of each particle.
std::vector<int> pair_contact_counts(const World& w);

// Solid fraction of the slab a < z < b over the full x-y cross-section of the domain,
// from the exact sphere-slab volumes.
double solid_fraction(const World& w, double a, double b);

// Mean number of particle-particle contacts per particle with its centre in a < z < b
// (walls excluded); `without_rattlers` skips particles with fewer than 2 contacts.
double coordination(const World& w, double a, double b, bool without_rattlers);

}  // namespace tsubu
