// The named results of one [[analyses]] entry on the current state (docs/scenario.md,
// [[analyses]]), for run.json and series.csv: every kind, the deposit measures included.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// (name, value) pairs: `<name>` first, then `<name>_<detail>` values:
//   solid_fraction: <name>, <name>_grains (centres in the slab);
//   coordination: <name>, <name>_no_rattlers (fewer than 2 contacts left out),
//                 <name>_no_rattlers_4 (fewer than 4), <name>_grains;
//   deposit_height: <name> (m above the floor);
//   porosity: <name> (Monte Carlo), <name>_standard_error, <name>_points, <name>_exact,
//             <name>_grains (centres in the slab);
//   segregation: <name> (Gamma, the small grains' share of the solid volume), <name>_grains;
//   kinetic_energy: <name> (J, translational + rotational, all grains), <name>_per_grain;
//   profiles: none (its profiles go to their own files, analysis/profiles.hpp).
std::vector<std::pair<std::string, double>> analysis_results(const AnalysisSpec& a, const World& w);

// The names analysis_results gives, in its order (they do not depend on the state).
std::vector<std::string> analysis_result_names(const AnalysisSpec& a);

// The unit of each of them, in the same order: "J" (kinetic_energy), "m" (deposit_height),
// "" for fractions, coordination numbers and counts.
std::vector<std::string> analysis_result_units(const AnalysisSpec& a);

// The columns of series.csv before the analyses' results, in its order: time, the energies,
// contacts and max_overlap_ratio; wall<k>_displacement and wall<k>_load per moving wall k;
// level<k> per block-step level k; particles and inflow_mass with an inflow.
std::vector<std::string> series_columns(const Scenario& sc);

}  // namespace tsubu
