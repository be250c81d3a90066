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

}  // namespace tsubu
