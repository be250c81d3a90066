// Normal contact models (docs/engine.md). Each is a small value type holding the
// material-pair constants; force() depends only on the contact geometry and its history.
#pragma once
#include <cmath>

#include "tsubu/contact/geometry.hpp"

namespace tsubu {

// Damping ratio that gives restitution e for a linear spring-dashpot:
// beta = -ln e / sqrt(pi^2 + ln^2 e)  (0 for e = 1).
inline double damping_ratio(double e) {
  const double l = std::log(e);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

// Model C, linear spring-dashpot (Cundall & Strack 1979):
// F_n = k_n delta - eta_n v_n, eta_n = 2 beta sqrt(m* k_n).
struct LinearDashpot {
  static constexpr const char* name = "linear (C)";
  double k_n = 0;   // N/m
  double beta = 0;  // damping ratio from the restitution

  // Duration of a collision (half a period of the undamped spring), s; any impact speed.
  double collision_time(double m_eff, double, double) const { return M_PI * std::sqrt(m_eff / k_n); }
  bool collision_longer_than(double m_eff, double r_eff, double u, double t) const { return collision_time(m_eff, r_eff, u) > t; }
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
  static constexpr const char* name = "hertz_tsuji (T)";
  double e_star = 0;  // effective modulus E*, Pa
  double alpha = 0;   // alpha(e) = sqrt(5) |ln e| / sqrt(ln^2 e + pi^2)

  static double alpha_of(double e) { return std::sqrt(5.0) * damping_ratio(e); }
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
  static constexpr const char* name = "hertz_sediment (H)";
  double e_star = 0;  // Pa
  double alpha = 0;   // paper Table 1: 0.2
  bool tsuji_dashpot = false;
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
    const T eta = tsuji_dashpot ? T(alpha) * sqrt(T(K * g.m_eff) * root_delta)
                                : T(alpha * std::sqrt(K * g.m_eff * std::sqrt(g.d_mean)));
    return {f_el - eta * g.v_n, T(1.5 * K) * root_delta, eta, T(0.4) * f_el * g.delta, f_el};
  }
};

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
  static constexpr const char* name = "hooke_hysteresis (HH)";
  double e_star = 0;         // effective modulus E*, Pa
  double v_c = 0;            // characteristic velocity, m/s
  double c_k2 = 0;           // k2max / k_n, > 1
  double c_kc = 0;           // k_c / k_n, >= 0
  double phi_f = 0;          // plasticity depth, fraction of 2R*
  double log_e = 0;          // ln(restitution), <= 0
  bool no_tension = false;   // clamp F_n >= 0

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
