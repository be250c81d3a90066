// Normal contact models C, T and H (docs/engine.md; HH and P, F have files of their own).
// Each is a small value type holding the material-pair constants, whose force() depends only
// on the contact geometry and its history, with its traits beside it (contact/law_traits.hpp).
#pragma once
#include <array>
#include <cmath>
#include <limits>

#include "tsubu/contact/geometry.hpp"
#include "tsubu/contact/law_traits.hpp"

namespace tsubu {

// Damping ratio that gives restitution e for a linear spring-dashpot:
// beta = -ln e / sqrt(pi^2 + ln^2 e)  (0 for e = 1).
inline double damping_ratio(double e) {
  const double l = std::log(e);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

// The spring constant k_n of the linear springs (models C, P and F).
inline constexpr LawKey kStiffnessKey = law_key::required("stiffness", KeyKind::positive, "the spring constant k_n in N/m");

// Model C, linear spring-dashpot (Cundall & Strack 1979):
// F_n = k_n delta - eta_n v_n, eta_n = 2 beta sqrt(m* k_n).
struct LinearDashpot {
  static constexpr std::string_view name = "linear";
  static constexpr std::string_view label = "linear (C)";
  static constexpr std::array keys = {kStiffnessKey};
  static constexpr bool linear_spring = true;  // a linear tangential spring takes the same beta
  double k_n = 0;   // N/m
  double beta = 0;  // damping ratio from the restitution

  static LinearDashpot build(const LawInput& in) { return {in.number("stiffness"), damping_ratio(in.restitution)}; }

  // Duration of a collision (half a period of the undamped spring), s; any impact speed.
  double collision_time(double m_eff, double, double) const { return M_PI * std::sqrt(m_eff / k_n); }
  // Elastic peak overlap of a head-on collision at approach speed u, m.
  double peak_overlap(double m_eff, double, double u) const { return u * std::sqrt(m_eff / k_n); }

  template <class G>
  [[gnu::always_inline]] BasicNormalForce<typename G::Number> force(const G& g, ContactHistory&) const {
    using T = typename G::Number;
    const double eta = 2.0 * beta * std::sqrt(g.m_eff * k_n);
    const T f_el = T(k_n) * g.delta;
    return {f_el - T(eta) * g.v_n, T(k_n), T(eta), T(0.5 * k_n) * g.delta * g.delta, f_el};
  }
};

// Hertz's stiffness K = 4/3 E* sqrt(R*) (F = K delta^{3/2}), N/m^{3/2}.
inline double hertz_stiffness(double e_star, double r_eff) { return (4.0 / 3.0) * e_star * std::sqrt(r_eff); }

// Duration of a Hertz collision at impact speed u (Sota & Watanabe Eq. 20):
// t_coll = 2.94 (m*^2 / (K^2 u))^{1/5}, K = 4/3 E* sqrt(R*).
inline double hertz_collision_time(double e_star, double m_eff, double r_eff, double u) {
  const double K = hertz_stiffness(e_star, r_eff);
  return 2.94 * std::pow(m_eff * m_eff / (K * K * u), 0.2);
}

// The elastic peak overlap of that collision: (15 m* u^2 / (16 E* sqrt(R*)))^(2/5), m.
inline double hertz_peak_overlap(double e_star, double m_eff, double r_eff, double u) {
  return std::pow(15 * m_eff * u * u / (16 * e_star * std::sqrt(r_eff)), 0.4);
}

// Whether that duration exceeds t, without the fifth root: m*^2 / (K^2 u) > (t / 2.94)^5.
// The block steps compare collision times with other bounds at every contact evaluation,
// and mostly need no more than the comparison.
inline bool hertz_collision_longer_than(double e_star, double m_eff, double r_eff, double u, double t) {
  const double K = hertz_stiffness(e_star, r_eff);
  const double s = t / 2.94, s2 = s * s;
  return m_eff * m_eff / (K * K * u) > s2 * s2 * s;
}

// Model T, Hertz with Tsuji damping (Tsuji, Tanaka & Ishida 1992):
// F_n = K delta^{3/2} - alpha sqrt(m* K) delta^{1/4} v_n, K = 4/3 E* sqrt(R*).
struct HertzTsuji {
  static constexpr std::string_view name = "hertz_tsuji";
  static constexpr std::string_view label = "hertz_tsuji (T)";
  double e_star = 0;  // effective modulus E*, Pa
  double alpha = 0;   // alpha(e) = sqrt(5) |ln e| / sqrt(ln^2 e + pi^2)

  static double alpha_of(double e) { return std::sqrt(5.0) * damping_ratio(e); }
  static HertzTsuji build(const LawInput& in) { return {in.effective_modulus(), alpha_of(in.restitution)}; }
  double collision_time(double m_eff, double r_eff, double u) const { return hertz_collision_time(e_star, m_eff, r_eff, u); }
  bool collision_longer_than(double m_eff, double r_eff, double u, double t) const {
    return hertz_collision_longer_than(e_star, m_eff, r_eff, u, t);
  }
  double peak_overlap(double m_eff, double r_eff, double u) const { return hertz_peak_overlap(e_star, m_eff, r_eff, u); }

  template <class G>
  [[gnu::always_inline]] BasicNormalForce<typename G::Number> force(const G& g, ContactHistory&) const {
    using T = typename G::Number;
    using std::sqrt;
    const double K = hertz_stiffness(e_star, g.r_eff);
    const T root_delta = sqrt(g.delta);
    const T f_el = T(K) * g.delta * root_delta;
    const T eta = T(alpha) * sqrt(T(g.m_eff * K) * root_delta);  // delta^{1/4} inside the root
    // Linear-equivalent stiffness dF/ddelta = 3/2 K delta^{1/2}.
    return {f_el - eta * g.v_n, T(1.5 * K) * root_delta, eta, T(0.4) * f_el * g.delta, f_el};
  }
};

// Model H, Hertz with a dashpot as used for sediment (Sota & Watanabe Eqs. 9-14):
// F_n = K delta^{3/2} - eta_n v_n. Eq. 14 reads two ways (docs/engine.md, "Normal models"):
// as printed, eta_n = alpha sqrt(K m* dbar^{1/2}), a constant dashpot (dbar = (d_i + d_j)/2);
// in Tsuji's form, eta_n = alpha sqrt(K m* delta^{1/2}) (`tsuji_dashpot`), for which alpha
// sets a restitution independent of the impact speed, as the paper's text says it does.
struct HertzSediment {
  static constexpr std::string_view name = "hertz_sediment";
  static constexpr std::string_view label = "hertz_sediment (H)";
  static constexpr std::array keys = {
      law_key::number("alpha", KeyKind::positive, 0.2, "the dashpot constant alpha of Eq. 14"),
      law_key::choice("dashpot", {"constant", "tsuji"}, "the dashpot of Eq. 14: as printed, or Tsuji's form")};
  double e_star = 0;  // Pa
  double alpha = 0;   // paper Table 1: 0.2
  bool tsuji_dashpot = false;

  static HertzSediment build(const LawInput& in) {
    return {in.effective_modulus(), in.number("alpha"), in.is("dashpot", "tsuji")};
  }
  // The tangential dashpot's ratio beta/alpha as printed, 1/sqrt(2(1 - sigma)) (docs/engine.md,
  // "Sota & Watanabe's contact law, read both ways").
  static double tangential_dashpot_ratio(double sigma) { return 1.0 / std::sqrt(2.0 * (1.0 - sigma)); }
  double collision_time(double m_eff, double r_eff, double u) const { return hertz_collision_time(e_star, m_eff, r_eff, u); }
  bool collision_longer_than(double m_eff, double r_eff, double u, double t) const {
    return hertz_collision_longer_than(e_star, m_eff, r_eff, u, t);
  }
  double peak_overlap(double m_eff, double r_eff, double u) const { return hertz_peak_overlap(e_star, m_eff, r_eff, u); }

  template <class G>
  [[gnu::always_inline]] BasicNormalForce<typename G::Number> force(const G& g, ContactHistory&) const {
    using T = typename G::Number;
    using std::sqrt;
    const double K = hertz_stiffness(e_star, g.r_eff);
    const T root_delta = sqrt(g.delta);
    const T f_el = T(K) * g.delta * root_delta;
    // The choice is made on lane data (the overlap against -inf or +inf): GCC 12 does not
    // vectorise a select on a plain flag, and model H is the sedimentation runs' law.
    const double tsuji_above = tsuji_dashpot ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    const T eta = value(g.delta) > tsuji_above ? T(alpha) * sqrt(T(K * g.m_eff) * root_delta)
                                               : T(alpha * std::sqrt(K * g.m_eff * std::sqrt(g.d_mean)));
    return {f_el - eta * g.v_n, T(1.5 * K) * root_delta, eta, T(0.4) * f_el * g.delta, f_el};
  }
};

}  // namespace tsubu
