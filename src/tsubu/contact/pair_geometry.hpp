// What the laws see of a pair or wall contact, from the two bodies' kinematics. Written on
// the number type: on double for forces, on Dual (kinematics with their rates) for forces
// and their exact rates.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "tsubu/contact/geometry.hpp"

namespace tsubu {

// Velocity of particle i's surface at the contact point relative to its partner's, from the
// centres' relative velocity and the spins (the point lies arm_i from i's centre along -n
// and arm_j from j's along +n; a wall has no spin and arm_j = 0). The spins' part is summed
// first, so that the pair seen from j (n, v_centres and the two parts negated) gets this
// velocity negated to the bit: a pair's forces do not depend on which particle comes first.
template <class T>
Vector<T> contact_point_velocity(const Vector<T>& n, const T& arm_i, const T& arm_j, const Vector<T>& v_centres,
                                 const Vector<T>& wi, const Vector<T>& wj) {
  return v_centres + (cross(wi, -arm_i * n) - cross(wj, arm_j * n));
}

// Time until a gap closes at approach speed v and approach acceleration a (both along the
// line of centres, positive when closing): the first root of gap = v t + a t^2/2, infinity
// when it never closes. The block steps' gap rule (ContactStepRules::eta_gap).
inline double time_to_close(double gap, double v, double a) {
  const double disc = v * v + 2 * a * gap;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  const double denom = v + std::sqrt(disc);
  return denom > 0 ? 2 * gap / denom : std::numeric_limits<double>::infinity();
}

// Pair (i, j) with separation d = x_i - x_j (touching: |d| < r_i + r_j); velocities and
// spins of both.
template <class T>
BasicContactGeometry<T> pair_geometry(double ri, double rj, double mi, double mj, const Vector<T>& d,
                                      const Vector<T>& vi, const Vector<T>& vj, const Vector<T>& wi,
                                      const Vector<T>& wj) {
  using std::sqrt;
  const T dist = sqrt(norm2(d));
  BasicContactGeometry<T> g;
  g.n = d / dist;
  g.delta = T(ri + rj) - dist;
  const T arm_i = T(ri) - T(0.5) * g.delta, arm_j = T(rj) - T(0.5) * g.delta;
  const Vector<T> v_rel = contact_point_velocity(g.n, arm_i, arm_j, vi - vj, wi, wj);
  g.v_n = dot(v_rel, g.n);
  g.v_t = v_rel - g.v_n * g.n;
  const Vector<T> w_rel = wi - wj;
  g.w_roll = w_rel - dot(w_rel, g.n) * g.n;  // seen from j: negated, to the bit
  g.r_eff = ri * rj / (ri + rj);
  g.m_eff = mi * mj / (mi + mj);
  g.d_mean = ri + rj;
  g.d_small = 2.0 * std::min(ri, rj);
  return g;
}

// Particle (radius r, mass m) touching a wall with unit normal n at distance `dist` of its
// centre (on Dual with their rates); v_rel is the particle's velocity relative to the wall's
// surface.
template <class T>
[[gnu::always_inline]] inline BasicContactGeometry<T> wall_geometry(double r, double m, const Vector<T>& n, const T& dist,
                                                                    const Vector<T>& v_rel_centre, const Vector<T>& w) {
  BasicContactGeometry<T> g;
  g.n = n;
  g.delta = T(r) - dist;
  const T arm = T(r) - T(0.5) * g.delta;
  const Vector<T> v_rel = v_rel_centre + cross(w, -arm * g.n);
  g.v_n = dot(v_rel, g.n);
  g.v_t = v_rel - g.v_n * g.n;
  g.w_roll = w - dot(w, g.n) * g.n;
  g.r_eff = r;
  g.m_eff = m;
  g.d_mean = 2.0 * r;
  g.d_small = 2.0 * r;
  return g;
}

}  // namespace tsubu
