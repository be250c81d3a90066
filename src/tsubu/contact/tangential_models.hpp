// Tangential contact models (docs/engine.md, "Tangential models"). Each returns the
// tangential force on particle i and updates the spring `xi` kept in the contact history.
// Their traits (contact/law_traits.hpp) stand beside them; their builders take what they
// need of the pair's normal law as a NormalSide.
#pragma once
#include <array>
#include <cmath>

#include "tsubu/contact/geometry.hpp"
#include "tsubu/contact/law_traits.hpp"

namespace tsubu {

// Carry the spring into the current tangent plane (keeping its length), then stretch it by
// the tangential displacement of this step. Written with selects, not branches, so that the
// force loop vectorises (a zero spring stays zero).
[[gnu::always_inline]] inline void advance_spring(Vec3& xi, const ContactGeometry& g) {
  turn_into_plane(xi, g.n);
  xi += g.v_t * g.dt;
}

// The same step on a spring with its rate (block steps, where a contact's step is long): the
// value moves as above by the tangential displacement of the step to second order, the
// integral of v_t over the step from its value and rate at the step's end,
// h v_t - h^2/2 dv_t/dt (the rectangle rule h v_t alone errs to first order in the step);
// the rate is that of the continuous spring at the end of the step,
// d xi/dt = v_t - n (xi . dn/dt), which keeps it in the turning tangent plane.
template <void (*Advance)(Vec3&, const ContactGeometry&)>
inline void advance_with_rate(DualVec3& xi, const DualContactGeometry& g) {
  Vec3 x = value(xi);
  const Vec3 mean_v_t = value(g.v_t) - (0.5 * g.dt) * rate(g.v_t);  // over the step, to second order
  const ContactGeometry plain{value(g.n), g.delta.v, g.v_n.v, mean_v_t, g.r_eff, g.m_eff, g.d_mean, g.d_small, g.dt, {}, 0};
  Advance(x, plain);
  xi = DualVec3(x, value(g.v_t) - dot(x, rate(g.n)) * plain.n);
}
inline void advance_spring(DualVec3& xi, const DualContactGeometry& g) { advance_with_rate<advance_spring>(xi, g); }

// The history of the tangential laws with a spring.
inline constexpr std::array kSpringHistory = {HistorySlot{"the tangential spring xi", Swap::negate}};

// Frictionless.
struct NoFriction {
  static constexpr std::string_view name = "none";
  static NoFriction build(const LawInput&, const NormalSide&) { return {}; }
  static constexpr double dashpot_ratio() { return 0; }  // eta_t / eta_n
  template <class G, class F, class V>
  V force(const G&, const F&, V&) const { return {}; }
};

// LIGGGHTS' order (tangential history): stretch the spring by v_t dt first, then drop its
// normal component (its length is not kept).
[[gnu::always_inline]] inline void advance_spring_projected(Vec3& xi, const ContactGeometry& g) {
  xi += g.v_t * g.dt;
  xi -= dot(xi, g.n) * g.n;
}
inline void advance_spring_projected(DualVec3& xi, const DualContactGeometry& g) {
  advance_with_rate<advance_spring_projected>(xi, g);
}

// Linear spring with Coulomb cap: F_t = -k_t xi - eta_t v_t; while |k_t xi| > mu |F_n| the
// force is mu |F_n| against xi and the spring is reset to -F_t/k_t (no damping while sliding).
// `projected` selects how the spring follows a turning contact plane: false rotates it into
// the new plane keeping its length (advance_spring), true is LIGGGHTS' projection
// (advance_spring_projected; used with model HH for step-for-step agreement).
struct LinearCoulomb {
  static constexpr std::string_view name = "linear_coulomb";
  static constexpr std::array keys = {  // kappa: 0 (the default) stands for the normal law's
      law_key::number("stiffness_ratio", KeyKind::positive, 0, "the tangential stiffness ratio k_t/k_n")};
  static constexpr auto history = kSpringHistory;
  double stiffness_ratio = 1;  // k_t / k_n (kappa)
  double damping_ratio = 1;    // eta_t / eta_n
  double mu = 0;               // friction coefficient
  bool projected = false;

  static LinearCoulomb build(const LawInput& in, const NormalSide& normal) {
    const double given = in.number("stiffness_ratio");
    const double kappa = given > 0 ? given : normal.stiffness_ratio;
    // A linear normal spring: eta_t = 2 beta sqrt(m* k_t) = sqrt(kappa) eta_n.
    const double ratio = normal.linear_spring ? std::sqrt(kappa) : normal.dashpot_ratio;
    return {kappa, ratio, in.friction, normal.projected_spring};
  }
  // eta_t / eta_n for the block steps' dashpot correction (ForceField::dashpot_response),
  // which takes the sticking contact's dashpot also while the contact slides.
  double dashpot_ratio() const { return damping_ratio; }

  template <class G, class V = Vector<typename G::Number>>
  [[gnu::always_inline]] V force(const G& g, const BasicNormalForce<typename G::Number>& fn, V& xi) const {
    using T = typename G::Number;
    using std::abs, std::sqrt;
    if (projected) advance_spring_projected(xi, g);
    else advance_spring(xi, g);
    const T k_t = T(stiffness_ratio) * fn.stiffness;
    const V spring = -k_t * xi;
    const T limit = T(mu) * abs(fn.f);
    const T s2 = norm2(spring);
    if (s2 > limit * limit) {
      const V f_t = spring * (limit / sqrt(s2));
      xi = f_t * (T(-1.0) / k_t);
      return f_t;
    }
    return spring - T(damping_ratio) * fn.damping * g.v_t;
  }
};

// Mindlin-type with slip (Sota & Watanabe Eqs. 10-14): xi capped at
// xi_max = mu (2-sigma)/(2(1-sigma)) delta (Eq. 11); chi = 1 - (1 - |xi|/xi_max)^{3/2};
// the spring's force -mu chi |f_c^n| xi/|xi| (Eq. 10, f_c^n the elastic normal force of
// Eq. 9) and the dashpot -eta_t v_t (Eq. 13). Eq. 10 reads two ways (docs/engine.md,
// "Tangential models"): as printed, the dashpot is added on top of the capped spring
// (`bound_whole_force` false: |F_t| may exceed mu |f_c^n| while the contact slides fast);
// bounded, the whole force F_t is scaled back to mu |f_c^n| where it exceeds it (the spring
// keeps its stretch, which is already capped at xi_max).
struct MindlinSlip {
  static constexpr std::string_view name = "mindlin";
  static constexpr std::array keys = {law_key::choice(
      "friction_bound", {"spring", "total"}, "what Eq. 10 bounds: the spring's force (as printed) or the total")};
  static constexpr auto history = kSpringHistory;
  double mu = 0;
  double sigma = 0;          // Poisson's ratio of the pair
  double damping_ratio = 1;  // eta_t / eta_n
  bool bound_whole_force = false;

  static MindlinSlip build(const LawInput& in, const NormalSide& normal) {
    return {in.friction, in.poisson(), normal.dashpot_ratio, in.is("friction_bound", "total")};
  }
  double dashpot_ratio() const { return damping_ratio; }

  template <class G, class V = Vector<typename G::Number>>
  [[gnu::always_inline]] V force(const G& g, const BasicNormalForce<typename G::Number>& fn, V& xi) const {
    using T = typename G::Number;
    using std::abs, std::sqrt;
    advance_spring(xi, g);
    const T xi_max = T(mu * (2.0 - sigma) / (2.0 * (1.0 - sigma))) * g.delta;
    const T len = norm(xi);
    const bool slips = len > xi_max;
    xi *= slips ? xi_max / len : T(1.0);  // the spring never exceeds xi_max
    const T stretch = slips ? xi_max : len;
    const T free = T(1.0) - stretch / xi_max;
    const T chi = T(1.0) - free * sqrt(free);  // 1 - (1 - |xi|/xi_max)^{3/2}
    const T limit = T(mu) * abs(fn.elastic);   // mu |f_c^n|
    const T pull = stretch > T(0.0) && xi_max > T(0.0) ? chi * limit / stretch : T(0.0);
    const V f_t = -(T(damping_ratio) * fn.damping) * g.v_t - pull * xi;
    // A select, not a branch: the force loop stays a vector loop (f_t * 1 is f_t, bit for bit).
    const T f2 = norm2(f_t);
    return f_t * (bound_whole_force && f2 > limit * limit ? limit / sqrt(f2) : T(1.0));
  }
};

}  // namespace tsubu
