// Normal contact models (spec/contact-models.md). Each is a small value type holding the
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

  NormalForce force(const ContactGeometry& g, ContactHistory&) const {
    const double eta = 2.0 * beta * std::sqrt(g.m_eff * k_n);
    return {k_n * g.delta - eta * g.v_n, k_n, eta, 0.5 * k_n * g.delta * g.delta};
  }
};

// Model T, Hertz with Tsuji damping (Tsuji, Tanaka & Ishida 1992):
// F_n = K delta^{3/2} - alpha sqrt(m* K) delta^{1/4} v_n, K = 4/3 E* sqrt(R*).
struct HertzTsuji {
  static constexpr const char* name = "hertz_tsuji (T)";
  double e_star = 0;  // effective modulus E*, Pa
  double alpha = 0;   // alpha(e) = sqrt(5) |ln e| / sqrt(ln^2 e + pi^2)

  static double alpha_of(double e) { return std::sqrt(5.0) * damping_ratio(e); }

  NormalForce force(const ContactGeometry& g, ContactHistory&) const {
    const double K = (4.0 / 3.0) * e_star * std::sqrt(g.r_eff);
    const double root_delta = std::sqrt(g.delta);
    const double f_el = K * g.delta * root_delta;
    const double eta = alpha * std::sqrt(g.m_eff * K * root_delta);  // delta^{1/4} inside the root
    // Linear-equivalent stiffness dF/ddelta = 3/2 K delta^{1/2}.
    return {f_el - eta * g.v_n, 1.5 * K * root_delta, eta, 0.4 * f_el * g.delta};
  }
};

// Model H, Hertz with a constant dashpot as used for sediment (Sota & Watanabe Eqs. 9-14):
// F_n = K delta^{3/2} - eta_n v_n, eta_n = alpha sqrt(K m* dbar^{1/2}).
struct HertzSediment {
  static constexpr const char* name = "hertz_sediment (H)";
  double e_star = 0;  // Pa
  double alpha = 0;   // paper Table 1: 0.2

  NormalForce force(const ContactGeometry& g, ContactHistory&) const {
    const double K = (4.0 / 3.0) * e_star * std::sqrt(g.r_eff);
    const double root_delta = std::sqrt(g.delta);
    const double f_el = K * g.delta * root_delta;
    const double eta = alpha * std::sqrt(K * g.m_eff * std::sqrt(g.d_mean));
    return {f_el - eta * g.v_n, 1.5 * K * root_delta, eta, 0.4 * f_el * g.delta};
  }
};

}  // namespace tsubu
