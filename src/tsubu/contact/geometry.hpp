// What a contact model sees of one contact (docs/engine.md, "Notation").
#pragma once
#include <cmath>

#include "tsubu/core/dual.hpp"
#include "tsubu/world/contact_list.hpp"

namespace tsubu {

// T = double for forces; T = Dual for forces with their rates (the kinematic quantities
// then carry their time derivatives; the constants of the pair do not change in time).
template <class T>
struct BasicContactGeometry {
  using Number = T;
  Vector<T> n;        // unit normal from j to i (wall: from the wall into the particle)
  T delta = 0;        // overlap R_i + R_j - |x_i - x_j| (wall: R_i - distance), m
  T v_n = 0;          // normal relative velocity, negative while approaching, m/s
  Vector<T> v_t;      // tangential relative velocity at the contact point, m/s
  double r_eff = 0;   // R* (wall: R_i), m
  double m_eff = 0;   // m* (wall: m_i), kg
  double d_mean = 0;  // (d_i + d_j)/2 (wall: d_i), m
  double d_small = 0; // min(d_i, d_j) (wall: d_i), m
  double dt = 0;      // time since the contact was last evaluated (the step), s
  Vector<T> w_roll;   // relative rolling velocity: omega_i - omega_j (wall: omega_i) in the contact plane, rad/s
  double rolling_inertia = 0;  // I_r = 1/(1/(I_i + m_i R_i^2) + 1/(I_j + m_j R_j^2)) (wall: I_i + m_i R_i^2), kg m^2
};
using ContactGeometry = BasicContactGeometry<double>;
using DualContactGeometry = BasicContactGeometry<Dual>;

// What a normal model returns: the normal force (positive repulsive), its linear-equivalent
// stiffness and damping coefficient (the tangential models scale theirs from these), the
// elastic energy stored in the normal spring, the elastic part of the force (the dashpot
// left out: Sota & Watanabe's f_c^n, Eq. 9, which bounds their friction, Eq. 10), and for
// models that correct positions
// (`corrects_position`), how much the gap must open now (m; split between the two particles
// like an impulse).
template <class T>
struct BasicNormalForce {
  T f = 0;
  T stiffness = 0;
  T damping = 0;
  T energy = 0;
  T elastic = 0;
  double gap_shift = 0;
};
using NormalForce = BasicNormalForce<double>;

// Turns a history vector of the contact plane into the plane of normal n, keeping its
// length (a zero vector stays zero). Written with selects, not branches, so that the force
// loop vectorises.
[[gnu::always_inline]] inline void turn_into_plane(Vec3& v, const Vec3& n) {
  const double len2 = norm2(v);
  const Vec3 projected = v - dot(v, n) * n;
  const double p2 = norm2(projected);
  const double keep_length = p2 > 0 ? std::sqrt(len2 / p2) : 0.0;
  v = projected * keep_length;
}

template <class Normal>
constexpr bool corrects_position_v = requires { Normal::corrects_position; };

}  // namespace tsubu
