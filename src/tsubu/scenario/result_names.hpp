// The names of the results of an [[analyses]] entry (docs/scenario.md, [[analyses]]): what a
// [[stop]] may name, the columns of series.csv and the keys of run.json. Their values are
// the analyses' (analysis/results.hpp).
#pragma once
#include <string>
#include <vector>

#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

// `<name>` first, then `<name>_<detail>` values:
//   solid_fraction: <name>, <name>_grains (centres in the slab);
//   coordination: <name>, <name>_no_rattlers (fewer than 2 contacts left out),
//                 <name>_no_rattlers_4 (fewer than 4), <name>_grains;
//   deposit_height: <name> (m above the floor);
//   porosity: <name> (Monte Carlo), <name>_standard_error, <name>_points, <name>_exact,
//             <name>_grains (centres in the slab);
//   segregation: <name> (Gamma, the small grains' share of the solid volume), <name>_grains;
//   kinetic_energy: <name> (J, translational + rotational, all grains), <name>_per_grain,
//                   <name>_speed_rms (m/s, mass-weighted rms speed);
//   profiles: none (its profiles go to their own files, analysis/profiles.hpp).
std::vector<std::string> analysis_result_names(const AnalysisSpec& a);

// The scenario's source whose grains arrive during the run (source = "inflow" or
// "insertion"), if it has one (at most one); nullptr without.
const ParticleSource* inflow_source(const Scenario& sc);

// The built-in columns of series.csv, before the analyses' results: time, the energies,
// contacts and largest overlap; two per moving wall; one per block-step level; with an
// inflow, the particles and the inflow's mass in the box.
std::vector<std::string> series_columns(const Scenario& sc);

}  // namespace tsubu
