#include "tsubu/scenario/result_names.hpp"


namespace tsubu {

std::vector<std::string> analysis_result_names(const AnalysisSpec& a) {
  const std::string& n = a.name;
  switch (a.kind) {
    case AnalysisSpec::Kind::solid_fraction: return {n, n + "_grains"};
    case AnalysisSpec::Kind::coordination: return {n, n + "_no_rattlers", n + "_no_rattlers_4", n + "_grains"};
    case AnalysisSpec::Kind::deposit_height: return {n};
    case AnalysisSpec::Kind::porosity: return {n, n + "_standard_error", n + "_points", n + "_exact", n + "_grains"};
    case AnalysisSpec::Kind::segregation: return {n, n + "_grains"};
    case AnalysisSpec::Kind::kinetic_energy: return {n, n + "_per_grain", n + "_speed_rms"};
    case AnalysisSpec::Kind::profiles: return {};
  }
  return {};
}

const ParticleSource* inflow_source(const Scenario& sc) {
  for (const ParticleSource& src : sc.sources)
    if (src.kind == ParticleSource::Kind::inflow || src.kind == ParticleSource::Kind::insertion) return &src;
  return nullptr;
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
  if (sc.domain.any_open()) columns.insert(columns.end(), {"outflow_count", "outflow_mass"});
  return columns;
}

}  // namespace tsubu
