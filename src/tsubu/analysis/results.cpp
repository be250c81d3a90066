#include "tsubu/analysis/results.hpp"

#include <cmath>
#include <stdexcept>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/core/exact_sum.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

namespace {

// The values of analysis_result_names(a), in its order.
std::vector<double> analysis_values(const AnalysisSpec& a, const World& w) {
  if (a.kind == AnalysisSpec::Kind::profiles) return {};  // written to profiles/ (analysis/profiles.hpp)
  const Packing p = packing_of(w);
  const double grains = static_cast<double>(grains_in_slab(p.position, a.z_low, a.z_high));
  switch (a.kind) {
    case AnalysisSpec::Kind::solid_fraction: return {solid_fraction(p, a.z_low, a.z_high), grains};
    case AnalysisSpec::Kind::coordination: {
      const Coordination c = coordination_numbers(p.position, pair_contact_counts(w), a.z_low, a.z_high);
      return {c.all, c.without_rattlers_2, c.without_rattlers_4, grains};
    }
    case AnalysisSpec::Kind::deposit_height:
      return {a.slice_rule ? deposit_height(p, a.slices) : surface_height(p, a.surface)};
    case AnalysisSpec::Kind::porosity: {
      const PorosityEstimate e = porosity_monte_carlo(p, a.z_low, a.z_high, a.points, a.seed);
      return {e.porosity, e.standard_error, static_cast<double>(e.points), 1 - solid_fraction(p, a.z_low, a.z_high), grains};
    }
    case AnalysisSpec::Kind::segregation:
      return {small_grain_share(p, a.z_low, a.z_high, a.small_diameter), grains};
    case AnalysisSpec::Kind::kinetic_energy: {
      const Energies e = energies(w, Vec3{});  // its kinetic parts
      const double kinetic = e.kinetic_translational + e.kinetic_rotational, n = static_cast<double>(w.particles.size());
      ExactSum mass_sum;
      for (double m : w.particles.mass) mass_sum += m;
      const double mass = mass_sum.value();
      return {kinetic, n > 0 ? kinetic / n : 0.0, mass > 0 ? std::sqrt(2 * e.kinetic_translational / mass) : 0.0};
    }
    case AnalysisSpec::Kind::profiles: break;  // above
  }
  return {};
}

}  // namespace

std::vector<std::pair<std::string, double>> analysis_results(const AnalysisSpec& a, const World& w) {
  std::vector<std::string> names = analysis_result_names(a);
  const std::vector<double> values = analysis_values(a, w);
  if (values.size() != names.size())
    throw std::logic_error("analysis \"" + a.name + "\": " + std::to_string(values.size()) + " values for " +
                           std::to_string(names.size()) + " result names");
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t k = 0; k < names.size(); ++k) out.emplace_back(std::move(names[k]), values[k]);
  return out;
}

std::vector<std::string> analysis_result_units(const AnalysisSpec& a) {
  std::vector<std::string> units;
  for (const std::string& name : analysis_result_names(a)) {
    const bool count = name.ends_with("_grains") || name.ends_with("_points");
    units.push_back(count                                            ? ""
                    : name.ends_with("_speed_rms")                 ? "m/s"
                    : a.kind == AnalysisSpec::Kind::kinetic_energy ? "J"
                    : a.kind == AnalysisSpec::Kind::deposit_height ? "m"
                                                                   : "");
  }
  return units;
}

}  // namespace tsubu
