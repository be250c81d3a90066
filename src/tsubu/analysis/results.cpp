#include "tsubu/analysis/results.hpp"

#include "tsubu/analysis/measures.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

std::vector<std::pair<std::string, double>> analysis_results(const AnalysisSpec& a, const World& w) {
  if (a.kind == AnalysisSpec::Kind::profiles) return {};  // written to profiles/ (analysis/profiles.hpp)
  const Packing p = packing_of(w);
  const double grains = static_cast<double>(grains_in_slab(p.position, a.z_low, a.z_high));
  switch (a.kind) {
    case AnalysisSpec::Kind::solid_fraction: return {{a.name, solid_fraction(p, a.z_low, a.z_high)}, {a.name + "_grains", grains}};
    case AnalysisSpec::Kind::coordination: {
      const Coordination c = coordination_numbers(p.position, pair_contact_counts(w), a.z_low, a.z_high);
      return {{a.name, c.all},
              {a.name + "_no_rattlers", c.without_rattlers_2},
              {a.name + "_no_rattlers_4", c.without_rattlers_4},
              {a.name + "_grains", grains}};
    }
    case AnalysisSpec::Kind::deposit_height: return {{a.name, deposit_height(p, a.slices)}};
    case AnalysisSpec::Kind::porosity: {
      const PorosityEstimate e = porosity_monte_carlo(p, a.z_low, a.z_high, a.points, a.seed);
      return {{a.name, e.porosity},
              {a.name + "_standard_error", e.standard_error},
              {a.name + "_points", static_cast<double>(e.points)},
              {a.name + "_exact", 1 - solid_fraction(p, a.z_low, a.z_high)},
              {a.name + "_grains", grains}};
    }
    case AnalysisSpec::Kind::segregation:
      return {{a.name, small_grain_share(p, a.z_low, a.z_high, a.small_diameter)}, {a.name + "_grains", grains}};
    case AnalysisSpec::Kind::kinetic_energy: {
      const Energies e = energies(w);
      const double kinetic = e.kinetic_translational + e.kinetic_rotational, n = static_cast<double>(w.particles.size());
      return {{a.name, kinetic}, {a.name + "_per_grain", n > 0 ? kinetic / n : 0.0}};
    }
    case AnalysisSpec::Kind::profiles: break;  // above
  }
  return {};
}

std::vector<std::string> analysis_result_names(const AnalysisSpec& a) {
  std::vector<std::string> names;
  for (auto& [name, value] : analysis_results(a, World{})) names.push_back(std::move(name));  // no grains: cheap
  return names;
}

std::vector<std::string> analysis_result_units(const AnalysisSpec& a) {
  std::vector<std::string> units;
  for (const std::string& name : analysis_result_names(a)) {
    const bool count = name.ends_with("_grains") || name.ends_with("_points");
    units.push_back(count                                            ? ""
                    : a.kind == AnalysisSpec::Kind::kinetic_energy ? "J"
                    : a.kind == AnalysisSpec::Kind::deposit_height ? "m"
                                                                   : "");
  }
  return units;
}

std::vector<std::string> series_columns(const Scenario& sc) {
  std::vector<std::string> columns = {"time",    "kinetic_translational", "kinetic_rotational", "potential_gravity",
                                      "elastic", "contacts",              "max_overlap_ratio"};
  for (std::size_t k = 0; k < sc.walls.size(); ++k)
    if (!sc.walls[k].motion.empty())
      for (const char* what : {"_displacement", "_load"}) columns.push_back("wall" + std::to_string(k) + what);
  if (sc.integrator == Integrator::block_hermite)
    for (int k = 0; k <= sc.block_steps.levels; ++k) columns.push_back("level" + std::to_string(k));
  if (inflow_source(sc)) columns.insert(columns.end(), {"particles", "inflow_mass"});
  return columns;
}

}  // namespace tsubu
