// Energy-conserving normal contact (Fujioka & Ushijima; docs/engine.md, models P and
// F). Both exist only with the symplectic Euler scheme v <- v + F/m dt, x <- x + v dt, whose
// future plane is d_{j+1} = d_j + u_{j+1}. Dimensionless along n, for step dt and
// characteristic length d_c:
//   u = -v_n dt / d_c (approach per step), d = delta / d_c, a = k_n dt^2 / m*, s = u / d,
// and an impulse f changes u by f; the real force over the step is F_n = -f m* d_c / dt^2.
// The energy (a d^2 + u^2)/2 is what the model conserves.
#pragma once
#include <array>
#include <cmath>
#include <limits>

#include "tsubu/contact/geometry.hpp"
#include "tsubu/contact/law_traits.hpp"
#include "tsubu/contact/normal_models.hpp"

namespace tsubu {

namespace energy_contact {

// Dimensionless state of a touching pair.
struct State {
  double u, d, a, s, d_c;
};

inline State state_of(const ContactGeometry& g, double k_n, double characteristic_length) {
  State st;
  st.d_c = characteristic_length > 0 ? characteristic_length : g.d_small;
  st.u = -g.v_n * g.dt / st.d_c;
  st.d = g.delta / st.d_c;
  st.a = k_n * g.dt * g.dt / g.m_eff;
  st.s = st.u / st.d;
  return st;
}

// Modes 2-4: the impulse of a step from a state inside the contact (s < 1).
inline double interior_impulse(const State& st) {
  const double a = st.a, s = st.s, d = st.d;
  const bool eq21 = (s > 0) || (a < 1 && s * s <= 1 - a);  // modes 2 and 3 (s >= -sqrt(1-a))
  if (eq21) {
    const double root = std::sqrt(s * s * (a + 1) + a * a);
    // Eq. 21 (negative root): rebound while keeping the energy; d_{j+1} = d (1 - root)/(1 + a).
    // Our addition: when that would leave d_{j+1} <= 0 the pair separates this step, and
    // Eq. 23 is used so that no spring energy is left behind.
    if (root < 1) return -(d / (1 + a)) * ((a + 1) * s + a + root);
  }
  return -d * (s + std::sqrt(s * s + a));  // Eq. 23, mode 4: separation, all energy kinetic
}

// The force and the depth correction of an impulse `f` and a correction `d_hat - d`.
inline NormalForce to_force(const ContactGeometry& g, const State& st, double f, double depth_change, double k_n,
                            double beta) {
  NormalForce out;
  out.f = -f * g.m_eff * st.d_c / (g.dt * g.dt);
  out.stiffness = k_n;
  out.damping = 2.0 * beta * std::sqrt(g.m_eff * k_n);  // for the tangential damping only
  out.energy = 0.5 * k_n * g.delta * g.delta;
  out.elastic = out.f;  // an impulse per step: no elastic part of its own
  out.gap_shift = -depth_change * st.d_c;  // the gap opens by what the depth loses
  return out;
}

// The traits models P and F share: the keys, the integrator (symplectic Euler, on fixed
// steps) and the builder.
inline constexpr std::array keys = {
    kStiffnessKey,  // d_c: 0 (the default) stands for the pair's smaller diameter
    law_key::number("characteristic_length", KeyKind::positive, 0, "the length d_c in m of the dimensionless variables")};
inline constexpr std::array integrators = {kFixedSteps, kSymplecticEulerOnly};
template <class Model>
Model build(const LawInput& in) {
  return {in.number("stiffness"), in.restitution, damping_ratio(in.restitution), in.number("characteristic_length")};
}

}  // namespace energy_contact

// Model P: the paper's model, with the contact-step state correction.
struct EnergyConserving {
  static constexpr std::string_view name = "energy_conserving";
  static constexpr std::string_view label = "energy_conserving (P)";
  static constexpr auto keys = energy_contact::keys;
  static constexpr auto integrators = energy_contact::integrators;
  static constexpr bool linear_spring = true;      // the tangential models see k_n and 2 beta sqrt(m* k_n)
  static constexpr bool exact_whatever_dt = true;  // the restitution in three steps: a long contact is no error of dt
  static constexpr bool corrects_position = true;
  double k_n = 0;                    // N/m
  double e = 1;                      // restitution
  double beta = 0;                   // damping ratio of e, for the tangential model
  double characteristic_length = 0;  // m, 0: the smaller diameter of the pair
  static EnergyConserving build(const LawInput& in) { return energy_contact::build<EnergyConserving>(in); }
  // Half a period of the spring, s, and the elastic peak overlap at approach speed u, m.
  double collision_time(double m_eff, double, double) const { return M_PI * std::sqrt(m_eff / k_n); }
  double peak_overlap(double m_eff, double, double u) const { return u * std::sqrt(m_eff / k_n); }

  NormalForce force(const ContactGeometry& g, ContactHistory&) const {
    using namespace energy_contact;
    const State st = state_of(g, k_n, characteristic_length);
    if (st.s < 1) return to_force(g, st, interior_impulse(st), 0.0, k_n, beta);
    // Mode 1, the contact step: the touch happened 1/s of a step ago. Replace (d, u) by the
    // state of energy e^2 u^2 / 2 on the same line d = u/s (Eqs. 15, 17) ...
    const double a = st.a, s = st.s, u = st.u;
    const double f_hat = (e * s / std::sqrt(s * s + a) - 1) * u;
    const double u_hat = u + f_hat;
    const double d_hat = u_hat / s;
    // ... then take an energy-conserving step from it (Eq. 20, positive root; the paper
    // prints d_j where the corrected d_hat is meant).
    const double f_bar = -(d_hat / (1 + a)) * ((a + 1) * s + a - std::sqrt(s * s * (a + 1) + a * a));
    return to_force(g, st, f_hat + f_bar, d_hat - st.d, k_n, beta);
  }
};

// Model F: the authors' 2005 model as reconstructed in docs/engine.md ("F (reconstructed)"). No
// correction of the contact step; mode 1 split by the line s = 1/e.
struct EnergyConserving2005 {
  static constexpr std::string_view name = "energy_conserving_2005";
  static constexpr std::string_view label = "energy_conserving_2005 (F, reconstructed)";
  static constexpr auto keys = energy_contact::keys;
  static constexpr auto integrators = energy_contact::integrators;
  static constexpr bool linear_spring = true;
  static constexpr bool exact_whatever_dt = true;
  // What a non-finite force of this model means, for the message that stops the run.
  static constexpr std::string_view when_not_finite =
      "for energy_conserving_2005 this means the contact left the reconstructed model's range, (a+1) e^2 u^2 < a d^2:"
      " raise e or lower k_n dt^2/m*";
  double k_n = 0;
  double e = 1;
  double beta = 0;
  double characteristic_length = 0;
  static EnergyConserving2005 build(const LawInput& in) { return energy_contact::build<EnergyConserving2005>(in); }
  double collision_time(double m_eff, double, double) const { return M_PI * std::sqrt(m_eff / k_n); }
  double peak_overlap(double m_eff, double, double u) const { return u * std::sqrt(m_eff / k_n); }

  NormalForce force(const ContactGeometry& g, ContactHistory&) const {
    using namespace energy_contact;
    const State st = state_of(g, k_n, characteristic_length);
    if (st.s < 1) return to_force(g, st, interior_impulse(st), 0.0, k_n, beta);
    if (st.s >= 1 / e) return to_force(g, st, -(1 + e) * st.u, 0.0, k_n, beta);  // one-step rebound
    // Keep the contact-step state; the next state has energy e^2 u^2 / 2 with d' = d + u'.
    const double a = st.a, d = st.d, u = st.u;
    const double disc = (a + 1) * e * e * u * u - a * d * d;
    if (disc < 0)  // outside the model's range (small e, large a): stops the run as non-finite
      return to_force(g, st, std::numeric_limits<double>::quiet_NaN(), 0.0, k_n, beta);
    const double u_next = (-a * d + std::sqrt(disc)) / (a + 1);
    return to_force(g, st, u_next - u, 0.0, k_n, beta);
  }
};

}  // namespace tsubu
