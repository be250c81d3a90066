// Rolling resistance models (docs/contact-laws.md, "Rolling resistance"): the torque on
// particle i that resists the relative rolling of a contact's two bodies; the partner takes
// it negated. They read the relative rolling velocity w_r (geometry.hpp: omega_i - omega_j
// projected on the contact plane, so that twisting about n meets no resistance) and the
// normal force of the pair's normal law. Numbering of the equations: docs/contact-laws.md.
#pragma once
#include <array>
#include <cmath>

#include "tsubu/contact/geometry.hpp"
#include "tsubu/contact/law_traits.hpp"

namespace tsubu {

// Both models run on fixed steps only: the block steps' rates and dashpot response carry no
// rolling torque (and model CDT's torque jumps where w_r reverses: it has no rate there).
inline constexpr std::array kRollingIntegrators = {IntegratorRule{
    {"velocity_verlet", "symplectic_euler", ""}, "is defined on fixed time steps (the block steps carry no rolling torque)"}};
inline constexpr LawKey kRollingFrictionKey =
    law_key::required("rolling_friction", KeyKind::non_negative, "the coefficient of rolling friction mu_r");

// No rolling resistance (the default).
struct NoRolling {
  static constexpr std::string_view name = "none";
  static NoRolling build(const LawInput&) { return {}; }
  template <class G, class F>
  Vector<typename G::Number> torque(const G&, const F&, Vec3&) const { return {}; }
};

// Constant directional torque (Ai et al. 2011, model A), Eq. R1:
// M_r = -mu_r R* |F_n| w_r / |w_r|, zero while w_r = 0. It keeps no history.
struct ConstantDirectionalTorque {
  static constexpr std::string_view name = "cdt";
  static constexpr std::array keys = {kRollingFrictionKey};
  static constexpr auto integrators = kRollingIntegrators;
  double mu_r = 0;

  static ConstantDirectionalTorque build(const LawInput& in) { return {in.number("rolling_friction")}; }

  [[gnu::always_inline]] Vec3 torque(const ContactGeometry& g, const NormalForce& fn, Vec3&) const {
    const double w = std::sqrt(norm2(g.w_roll));
    const double limit = mu_r * g.r_eff * std::abs(fn.f);  // M_r^m, Eq. R2
    return g.w_roll * (w > 0 ? -limit / w : 0.0);
  }
};

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
  static constexpr auto integrators = kRollingIntegrators;
  static constexpr std::array history = {HistorySlot{"the rolling spring's torque M_r^k", Swap::negate}};
  double mu_r = 0;
  double eta_r = 0;

  static ElasticPlasticRolling build(const LawInput& in) { return {in.number("rolling_friction"), in.number("rolling_damping")}; }

  [[gnu::always_inline]] Vec3 torque(const ContactGeometry& g, const NormalForce& fn, Vec3& spring) const {
    turn_into_plane(spring, g.n);
    const double k_r = 2.25 * fn.stiffness * (mu_r * g.r_eff) * (mu_r * g.r_eff);  // Eq. R4
    spring -= (k_r * g.dt) * g.w_roll;                                              // Eq. R3
    const double limit = mu_r * g.r_eff * std::abs(fn.f);                           // Eq. R2
    const double s2 = norm2(spring);
    const bool full = s2 > limit * limit;  // fully mobilised: the spring slips, no dashpot
    spring *= full ? limit / std::sqrt(s2) : 1.0;
    const double c_r = full ? 0.0 : eta_r * 2.0 * std::sqrt(g.rolling_inertia * k_r);  // Eq. R5
    return spring - c_r * g.w_roll;
  }
};

}  // namespace tsubu
