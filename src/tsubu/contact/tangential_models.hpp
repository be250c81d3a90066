// Tangential contact models (spec/contact-models.md, "Tangential models"). Each returns the
// tangential force on particle i and updates the spring `xi` kept in the contact history.
#pragma once
#include <cmath>

#include "tsubu/contact/geometry.hpp"

namespace tsubu {

// Carry the spring into the current tangent plane (keeping its length), then stretch it by
// the tangential displacement of this step. Written with selects, not branches, so that the
// force loop vectorises (a zero spring stays zero).
[[gnu::always_inline]] inline void advance_spring(Vec3& xi, const ContactGeometry& g) {
  const double len2 = norm2(xi);
  const Vec3 projected = xi - dot(xi, g.n) * g.n;
  const double p2 = norm2(projected);
  const double keep_length = p2 > 0 ? std::sqrt(len2 / p2) : 0.0;
  xi = projected * keep_length + g.v_t * g.dt;
}

// Frictionless.
struct NoFriction {
  Vec3 force(const ContactGeometry&, const NormalForce&, Vec3&) const { return {}; }
};

// LIGGGHTS' order (tangential history): stretch the spring by v_t dt first, then drop its
// normal component (its length is not kept).
[[gnu::always_inline]] inline void advance_spring_projected(Vec3& xi, const ContactGeometry& g) {
  xi += g.v_t * g.dt;
  xi -= dot(xi, g.n) * g.n;
}

// Linear spring with Coulomb cap: F_t = -k_t xi - eta_t v_t; while |k_t xi| > mu |F_n| the
// force is mu |F_n| against xi and the spring is reset to -F_t/k_t (no damping while sliding).
// `projected` selects how the spring follows a turning contact plane: false rotates it into
// the new plane keeping its length (advance_spring), true is LIGGGHTS' projection
// (advance_spring_projected; used with model HH for step-for-step agreement).
struct LinearCoulomb {
  double stiffness_ratio = 1;  // k_t / k_n (kappa)
  double damping_ratio = 1;    // eta_t / eta_n
  double mu = 0;               // friction coefficient
  bool projected = false;

  [[gnu::always_inline]] Vec3 force(const ContactGeometry& g, const NormalForce& fn, Vec3& xi) const {
    if (projected) advance_spring_projected(xi, g);
    else advance_spring(xi, g);
    const double k_t = stiffness_ratio * fn.stiffness;
    const Vec3 spring = -k_t * xi;
    const double limit = mu * std::abs(fn.f);
    const double s2 = norm2(spring);
    if (s2 > limit * limit) {
      const Vec3 f_t = spring * (limit / std::sqrt(s2));
      xi = f_t * (-1.0 / k_t);
      return f_t;
    }
    return spring - damping_ratio * fn.damping * g.v_t;
  }
};

// Mindlin-type with slip (Sota & Watanabe Eqs. 10-11): xi capped at
// xi_max = mu (2-sigma)/(2(1-sigma)) delta; chi = 1 - (1 - |xi|/xi_max)^{3/2};
// F_t = -mu chi |F_n| xi/|xi| - eta_t v_t.
struct MindlinSlip {
  double mu = 0;
  double sigma = 0;          // Poisson's ratio of the pair
  double damping_ratio = 1;  // eta_t / eta_n

  [[gnu::always_inline]] Vec3 force(const ContactGeometry& g, const NormalForce& fn, Vec3& xi) const {
    advance_spring(xi, g);
    const double xi_max = mu * (2.0 - sigma) / (2.0 * (1.0 - sigma)) * g.delta;
    const double len = norm(xi);
    const bool slips = len > xi_max;
    xi *= slips ? xi_max / len : 1.0;  // the spring never exceeds xi_max
    const double stretch = slips ? xi_max : len;
    const double free = 1.0 - stretch / xi_max;
    const double chi = 1.0 - free * std::sqrt(free);  // 1 - (1 - |xi|/xi_max)^{3/2}
    const double pull = stretch > 0 && xi_max > 0 ? mu * chi * std::abs(fn.f) / stretch : 0.0;
    return -damping_ratio * fn.damping * g.v_t - pull * xi;
  }
};

}  // namespace tsubu
