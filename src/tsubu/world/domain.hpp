// The simulation box: bounds and periodic axes, with the minimum-image convention.
#pragma once
#include <array>
#include <cmath>
#include <string>

#include "tsubu/core/vec3.hpp"

namespace tsubu {

struct Domain {
  Vec3 lower, upper;                 // m
  std::array<bool, 3> periodic{};    // per axis x, y, z

  double length(int k) const { return upper[k] - lower[k]; }

  // Shortest vector from b to a under the periodic axes, for positions inside the box
  // (their difference is below one box length, so one shift is enough).
  Vec3 separation(const Vec3& a, const Vec3& b) const {
    Vec3 d = a - b;
    for (int k = 0; k < 3; ++k)
      if (periodic[k]) {
        const double L = length(k);
        if (d[k] > 0.5 * L) d[k] -= L;
        else if (d[k] < -0.5 * L) d[k] += L;
      }
    return d;
  }

  // Map a position back into the box along periodic axes.
  Vec3 wrap(Vec3 x) const {
    for (int k = 0; k < 3; ++k)
      if (periodic[k]) {
        x[k] -= length(k) * std::floor((x[k] - lower[k]) / length(k));
        if (x[k] >= upper[k]) x[k] = lower[k];  // round-off at the upper face
      }
    return x;
  }

  bool inside(const Vec3& x) const {
    for (int k = 0; k < 3; ++k)
      if (!periodic[k] && (x[k] < lower[k] || x[k] > upper[k])) return false;
    return true;
  }
};

// An infinite plane; `normal` is a unit vector pointing into the particles' side.
struct Wall {
  Vec3 point;
  Vec3 normal;
  int material = 0;

  double distance(const Vec3& x) const { return dot(x - point, normal); }
};

struct Material {
  std::string name;
  double density = 0;         // kg/m^3
  double youngs_modulus = 0;  // Pa
  double poisson = 0;         // -
};

}  // namespace tsubu
