// What a contact model sees of one contact (spec/contact-models.md, "Notation").
#pragma once
#include "tsubu/core/vec3.hpp"

namespace tsubu {

struct ContactGeometry {
  Vec3 n;             // unit normal from j to i (wall: from the wall into the particle)
  double delta = 0;   // overlap R_i + R_j - |x_i - x_j| (wall: R_i - distance), m
  double v_n = 0;     // normal relative velocity, negative while approaching, m/s
  Vec3 v_t;           // tangential relative velocity at the contact point, m/s
  double r_eff = 0;   // R* (wall: R_i), m
  double m_eff = 0;   // m* (wall: m_i), kg
  double d_mean = 0;  // (d_i + d_j)/2 (wall: d_i), m
  double d_small = 0; // min(d_i, d_j) (wall: d_i), m
  double dt = 0;      // time step, s
};

// Per-contact memory. `xi` is the tangential spring (a vector in the tangent plane); the
// `normal` slots belong to the normal model (each model documents what it keeps there).
struct ContactHistory {
  Vec3 xi;
  double normal[2] = {0, 0};
};

// What a normal model returns: the normal force (positive repulsive), its linear-equivalent
// stiffness and damping coefficient (the tangential models scale theirs from these), the
// elastic energy stored in the normal spring, and for models that correct positions
// (`corrects_position`), how much the gap must open now (m; split between the two particles
// like an impulse).
struct NormalForce {
  double f = 0;
  double stiffness = 0;
  double damping = 0;
  double energy = 0;
  double gap_shift = 0;
};

template <class Normal>
constexpr bool corrects_position_v = requires { Normal::corrects_position; };

}  // namespace tsubu
