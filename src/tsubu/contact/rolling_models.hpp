// Rolling resistance models (docs/contact-laws.md, "Rolling resistance"): the torque on
// particle i that resists the relative rolling of a contact's two bodies; the partner takes
// it negated. They read the relative rolling velocity w_r (geometry.hpp: omega_i - omega_j
// projected on the contact plane, so that twisting about n meets no resistance) and the
// normal force of the pair's normal law. Numbering of the equations: docs/contact-laws.md.
// Written on the number type: on Dual (block steps) the torque carries its rate along the
// predicted motion, and the history advances as on the fixed steps.
#pragma once
#include <array>
#include <cmath>

#include "tsubu/contact/geometry.hpp"
#include "tsubu/contact/law_traits.hpp"

namespace tsubu {

inline constexpr LawKey kRollingFrictionKey =
    law_key::required("rolling_friction", KeyKind::non_negative, "the coefficient of rolling friction mu_r");

// What a rolling model gives: its torque on i, and for the block steps its spring's
// stiffness k_r (N m/rad: the step rule resolves the spring's turning oscillation) and its
// dashpot's coefficient C_r (N m s/rad: the dashpot correction and the dashpots' step bound).
template <class T>
struct BasicRollingTorque {
  Vector<T> torque;
  double stiffness = 0;
  double damping = 0;
};

// No rolling resistance (the default).
struct NoRolling {
  static constexpr std::string_view name = "none";
  static NoRolling build(const LawInput&) { return {}; }
  template <class G, class T = typename G::Number>
  BasicRollingTorque<T> torque(const G&, const BasicNormalForce<T>&, Vector<T>&) const { return {}; }
};

// Constant directional torque (Ai et al. 2011, model A), Eq. R1:
// M_r = -mu_r R* |F_n| w_r / |w_r|, zero while w_r = 0. It keeps no history. Its rate is
// that of the bound and of w_r's direction, and has no value where w_r reverses (the torque
// jumps there, on either integrator).
struct ConstantDirectionalTorque {
  static constexpr std::string_view name = "cdt";
  static constexpr std::array keys = {kRollingFrictionKey};
  double mu_r = 0;

  static ConstantDirectionalTorque build(const LawInput& in) { return {in.number("rolling_friction")}; }

  template <class G, class T = typename G::Number>
  [[gnu::always_inline]] BasicRollingTorque<T> torque(const G& g, const BasicNormalForce<T>& fn, Vector<T>&) const {
    using std::abs, std::sqrt;
    const T w = sqrt(norm2(g.w_roll));
    const T limit = T(mu_r * g.r_eff) * abs(fn.f);  // M_r^m, Eq. R2
    return {g.w_roll * (w > T(0.0) ? -limit / w : T(0.0))};
  }
};

// The rolling spring's step (Eq. R3): carried into the current contact plane (keeping its
// length, as the tangential spring), then turned by -k_r w_r dt. On Dual the value moves
// alike and the rate is that of the continuous spring at the step's end,
// dM/dt = -k_r w_r - n (M . dn/dt), which keeps it in the turning plane.
[[gnu::always_inline]] inline void advance_rolling_spring(Vec3& spring, const Vec3& n, double k_r, const Vec3& w_roll,
                                                          double dt) {
  turn_into_plane(spring, n);
  spring -= (k_r * dt) * w_roll;
}
inline void advance_rolling_spring(DualVec3& spring, const DualVec3& n, Dual k_r, const DualVec3& w_roll, double dt) {
  Vec3 m = value(spring);
  advance_rolling_spring(m, value(n), k_r.v, value(w_roll), dt);
  spring = DualVec3(m, -k_r.v * value(w_roll) - dot(m, rate(n)) * value(n));
}

// Elastic-plastic spring-dashpot (Ai et al. 2011, model C). The spring torque M_r^k (the
// history slot, a vector in the contact plane turned with it as the tangential spring is)
// grows by -k_r w_r dt (Eq. R3) with k_r = 2.25 k_n mu_r^2 R*^2 (Eq. R4, k_n the normal
// law's stiffness at the current overlap) and is capped at M_r^m = mu_r R* |F_n| (Eq. R2).
// Below the cap a dashpot adds -C_r w_r, C_r = eta_r 2 sqrt(I_r k_r) (Eq. R5, I_r the
// contact's rolling inertia); at the cap the dashpot is off (the paper's f = 0).
struct ElasticPlasticRolling {
  static constexpr std::string_view name = "epsd";
  static constexpr std::array keys = {
      kRollingFrictionKey,
      law_key::number("rolling_damping", KeyKind::non_negative, 0, "the rolling damping ratio eta_r of the dashpot")};
  static constexpr std::array history = {HistorySlot{"the rolling spring's torque M_r^k", Swap::negate}};
  double mu_r = 0;
  double eta_r = 0;

  static ElasticPlasticRolling build(const LawInput& in) { return {in.number("rolling_friction"), in.number("rolling_damping")}; }

  template <class G, class T = typename G::Number>
  [[gnu::always_inline]] BasicRollingTorque<T> torque(const G& g, const BasicNormalForce<T>& fn, Vector<T>& spring) const {
    using std::abs, std::sqrt;
    const T k_r = T(2.25) * fn.stiffness * T(mu_r * g.r_eff) * T(mu_r * g.r_eff);  // Eq. R4
    advance_rolling_spring(spring, g.n, k_r, g.w_roll, g.dt);                       // Eq. R3
    const T limit = T(mu_r * g.r_eff) * abs(fn.f);                                  // Eq. R2
    const T s2 = norm2(spring);
    const bool full = s2 > limit * limit;  // fully mobilised: the spring slips, no dashpot
    spring *= full ? limit / sqrt(s2) : T(1.0);
    const T c_r = full ? T(0.0) : T(eta_r * 2.0) * sqrt(T(g.rolling_inertia) * k_r);  // Eq. R5
    return {spring - c_r * g.w_roll, value(k_r), value(c_r)};
  }
};

}  // namespace tsubu
