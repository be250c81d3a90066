#include "tsubu/contact/law.hpp"

#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace tsubu {

double effective_modulus(const Material& a, const Material& b) {
  return 1.0 / ((1 - a.poisson * a.poisson) / a.youngs_modulus + (1 - b.poisson * b.poisson) / b.youngs_modulus);
}

double effective_shear_modulus(const Material& a, const Material& b) {
  auto term = [](const Material& m) { return 2 * (2 - m.poisson) * (1 + m.poisson) / m.youngs_modulus; };
  return 1.0 / (term(a) + term(b));
}

double contact_time(const NormalModel& model, double m_eff, double r_eff, double u) {
  return std::visit([&](const auto& n) { return n.collision_time(m_eff, r_eff, u); }, model);
}

double peak_overlap(const NormalModel& model, double m_eff, double r_eff, double u) {
  return std::visit([&](const auto& n) { return n.peak_overlap(m_eff, r_eff, u); }, model);
}

PairLaw make_pair_law(const ContactSpec& spec, const Material& a, const Material& b) {
  const double e_star = effective_modulus(a, b);
  const double nu = 0.5 * (a.poisson + b.poisson);
  const double beta = damping_ratio(spec.restitution);
  PairLaw law;
  double tangential_damping = 1.0;  // eta_t / eta_n
  if (spec.normal == "linear") {
    law.normal = LinearDashpot{spec.stiffness, beta};
  } else if (spec.normal == "hertz_tsuji") {
    law.normal = HertzTsuji{e_star, HertzTsuji::alpha_of(spec.restitution)};
  } else if (spec.normal == "hertz_sediment") {
    law.normal = HertzSediment{e_star, spec.alpha, spec.tsuji_dashpot};
    tangential_damping = 1.0 / std::sqrt(2.0 * (1.0 - nu));  // beta_t = alpha / sqrt(2(1-sigma))
  } else if (spec.normal == "energy_conserving") {
    law.normal = EnergyConserving{spec.stiffness, spec.restitution, beta, spec.characteristic_length};
  } else if (spec.normal == "energy_conserving_2005") {
    law.normal = EnergyConserving2005{spec.stiffness, spec.restitution, beta, spec.characteristic_length};
  } else if (spec.normal == "hooke_hysteresis") {
    if (!(spec.max_stiffness_ratio > 1))
      throw std::invalid_argument("hooke_hysteresis needs max_stiffness_ratio > 1");
    law.normal = HookeHysteresis{e_star,
                                 spec.characteristic_velocity,
                                 spec.max_stiffness_ratio,
                                 spec.adhesion_stiffness_ratio,
                                 spec.plasticity_depth,
                                 std::log(spec.restitution),
                                 spec.no_tension};
    tangential_damping = spec.tangential_damping ? 1.0 : 0.0;
  } else {
    throw std::invalid_argument("unknown normal model " + spec.normal);
  }
  if (spec.tangential == "none") {
    law.tangential = NoFriction{};
  } else if (spec.tangential == "linear_coulomb") {
    const bool hh = spec.normal == "hooke_hysteresis";
    // HH: k_t = k_n and gamma_t = gamma_n (or 0), as LIGGGHTS' tangential history.
    const double kappa = spec.stiffness_ratio > 0 ? spec.stiffness_ratio : hh ? 1.0 : 2 * (1 - nu) / (2 - nu);
    // eta_t = 2 beta sqrt(m* k_t) = sqrt(kappa) eta_n for the linear model.
    const bool linear_spring = spec.normal == "linear" || spec.normal.rfind("energy_conserving", 0) == 0;
    const double ratio = linear_spring ? std::sqrt(kappa) : tangential_damping;
    law.tangential = LinearCoulomb{kappa, ratio, spec.friction, hh};
  } else if (spec.tangential == "mindlin") {
    law.tangential = MindlinSlip{spec.friction, nu, tangential_damping, spec.bound_whole_force};
  } else {
    throw std::invalid_argument("unknown tangential model " + spec.tangential);
  }
  return law;
}

bool LawTable::corrects_positions() const {
  for (const auto& l : laws)
    if (std::visit([](const auto& m) { return corrects_position_v<std::decay_t<decltype(m)>>; }, l.normal)) return true;
  return false;
}

std::string LawTable::without_rates() const {
  for (const auto& l : laws) {
    const char* name = std::visit(
        [](const auto& m) -> const char* {
          if constexpr (has_rates_v<std::decay_t<decltype(m)>>) return nullptr;
          else return m.name;
        },
        l.normal);
    if (name) return name;
  }
  return "";
}

bool LawTable::uniform() const {
  for (const auto& l : laws)
    if (l.normal.index() != laws.front().normal.index() || l.tangential.index() != laws.front().tangential.index())
      return false;
  return true;
}

}  // namespace tsubu
