// Model HH, Hooke/Hysteresis: an elastic-plastic-adhesive linear law with a history, as
// LIGGGHTS 3.8 `hooke/hysteresis` (docs/scenario.md, "Normal models").
#pragma once
#include <array>
#include <cmath>

#include "tsubu/contact/geometry.hpp"
#include "tsubu/contact/law_traits.hpp"

namespace tsubu {

// Model HH, Hooke/Hysteresis, step-for-step the model of LIGGGHTS 3.8 `hooke/hysteresis`
// (docs/engine.md "Model HH"). A linear spring k_n on virgin loading; un- and
// reloading along a stiffer line k2 that grows with the largest overlap h; an adhesive
// branch -k_c delta below it. History: h ("deltaMax") in normal[0].
//   k_n = 16/15 sqrt(R*) E* (15 m* v_c^2 / (16 sqrt(R*) E*))^{1/5}
//   k2max = c_k2 k_n (c_k2 > 1), k_c = c_kc k_n, delta_lim = k2max/(k2max - k_n) phi_f 2R*
//   case A, h >= delta_lim: F = k2max (delta - delta_lim) + k_n delta_lim, floored at -k_c delta
//   case B, h <  delta_lim: k2 = k_n + (k2max - k_n) h/delta_lim,
//                           F = min(k_n delta, k2 (delta - h) + k_n h), floored at -k_c delta
// On the floor (the adhesive branch) h is rewritten to the root of k2(h)(delta - h) + k_n h =
// -k_c delta, so that unloading continues and reloading starts from the adhesive line.
// F_n = F - gamma_n v_n with gamma_n = sqrt(4 m* k_n / (1 + (pi/ln e)^2)); optionally F_n >= 0.
struct HookeHysteresis {
  static constexpr std::string_view name = "hooke_hysteresis";
  static constexpr std::string_view label = "hooke_hysteresis (HH)";
  static constexpr std::array keys = {
      law_key::required("characteristic_velocity", KeyKind::positive, "the velocity v_c in m/s that sets k_n"),
      law_key::required("max_stiffness_ratio", KeyKind::above_one, "k2max/k_n"),
      law_key::number("adhesion_stiffness_ratio", KeyKind::non_negative, 0, "k_c/k_n"),
      law_key::required("plasticity_depth", KeyKind::positive, "the plasticity depth phi_f as a fraction of 2R*"),
      law_key::flag("no_tension", false, "whether F_n is clamped at 0"),
      law_key::flag("tangential_damping", true, "whether gamma_t = gamma_n (false: 0)")};
  static constexpr std::array integrators = {kFixedSteps};
  static constexpr std::array history = {HistorySlot{"the largest overlap h (LIGGGHTS' deltaMax)", Swap::keep}};
  // With its tangential partner as LIGGGHTS' tangential history: k_t = k_n, gamma_t = gamma_n
  // (or 0), the spring stretched first and then projected.
  static constexpr std::string_view default_tangential = "linear_coulomb";
  static constexpr bool projected_spring = true;
  double e_star = 0;         // effective modulus E*, Pa
  double v_c = 0;            // characteristic velocity, m/s
  double c_k2 = 0;           // k2max / k_n, > 1
  double c_kc = 0;           // k_c / k_n, >= 0
  double phi_f = 0;          // plasticity depth, fraction of 2R*
  double log_e = 0;          // ln(restitution), <= 0
  bool no_tension = false;   // clamp F_n >= 0
  bool tangential_damping = true;  // gamma_t = gamma_n (false: 0)

  static HookeHysteresis build(const LawInput& in) {
    return {in.effective_modulus(), in.number("characteristic_velocity"), in.number("max_stiffness_ratio"),
            in.number("adhesion_stiffness_ratio"), in.number("plasticity_depth"), std::log(in.restitution),
            in.flag("no_tension"), in.flag("tangential_damping")};
  }
  double tangential_dashpot_ratio(double) const { return tangential_damping ? 1.0 : 0.0; }
  static double tangential_stiffness_ratio(double) { return 1.0; }

  // Landry's stiffness (the operation order is LIGGGHTS', so that the values agree to the bit).
  double k_n(double r_eff, double m_eff) const {
    const double root_r = std::sqrt(r_eff);
    return 16. / 15. * root_r * e_star * std::pow(15. * m_eff * v_c * v_c / (16. * root_r * e_star), 0.2);
  }
  // Duration of a collision: the half period of the stiffest line k2max = c_k2 k_n, which
  // unloading follows after a deep contact, s.
  double collision_time(double m_eff, double r_eff, double) const { return M_PI * std::sqrt(m_eff / (c_k2 * k_n(r_eff, m_eff))); }
  // Elastic peak overlap on the loading line k_n, m.
  double peak_overlap(double m_eff, double r_eff, double u) const { return u * std::sqrt(m_eff / k_n(r_eff, m_eff)); }
  double gamma_n(double k, double m_eff) const {
    if (log_e == 0) return 0.0;  // e = 1: no damping
    const double r = M_PI / log_e;
    return std::sqrt(4. * m_eff * k / (1. + r * r));
  }
  double delta_lim(double k, double r_eff) const {
    const double k2max = k * c_k2;
    return (k2max / (k2max - k)) * phi_f * 2 * r_eff;
  }

  // Which part of the law gave the force (for tests and diagnostics).
  enum class Branch { virgin, unload_reload, beyond_limit, adhesive };

  // The elastic-plastic part F_hys for overlap delta; updates h (= normal[0]).
  double hysteresis(double k, double r_eff, double delta, double& h, Branch* branch = nullptr) const {
    Branch b_local;
    Branch& b = branch ? *branch : b_local;
    const double k2max = k * c_k2;
    const double kc = k * c_kc;
    if (delta > h) h = delta;
    const double lim = delta_lim(k, r_eff);
    double f;
    if (h >= lim) {  // case A: beyond the plasticity depth, k2 = k2max with no k_n cap
      f = k2max * (delta - lim) + k * lim;
      b = Branch::beyond_limit;
      if (f >= -kc * delta) return f;
    } else {         // case B
      const double k2 = k + (k2max - k) * h / lim;
      f = k2 * (delta - h) + k * h;
      b = Branch::virgin;
      if (f >= k * delta) return k * delta;  // virgin loading
      b = Branch::unload_reload;
      if (f > -kc * delta) return f;         // un- or reloading
    }
    b = Branch::adhesive;
    // Adhesive branch: the force is -k_c delta and h moves so that this point lies on the
    // un/reloading line of the new h.
    h = 0.5 * (delta + std::sqrt(delta * delta + 4 * ((k + kc) * delta * lim / (k2max - k))));
    return -kc * delta;
  }

  NormalForce force(const ContactGeometry& g, ContactHistory& hist) const {
    const double k = k_n(g.r_eff, g.m_eff);
    const double gamma = gamma_n(k, g.m_eff);
    const double f_hys = hysteresis(k, g.r_eff, g.delta, hist.normal[0]);
    double f = f_hys - gamma * g.v_n;
    if (no_tension && f < 0) f = 0;
    // Energy: what unloading along the current k2 line would give back (0 when tensile).
    const double lim = delta_lim(k, g.r_eff);
    const double h = hist.normal[0];
    const double k2 = h >= lim ? k * c_k2 : k + (k * c_k2 - k) * h / lim;
    const double energy = f_hys > 0 ? 0.5 * f_hys * f_hys / k2 : 0.0;
    return {f, k, gamma, energy, f_hys};
  }
};

}  // namespace tsubu
