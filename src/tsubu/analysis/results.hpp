// The results of one [[analyses]] entry on the current state (docs/scenario.md,
// [[analyses]]), for run.json and series.csv: every kind, the deposit measures included.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "tsubu/scenario/result_names.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// (name, value) pairs, by the names of analysis_result_names(a) (scenario/result_names.hpp).
std::vector<std::pair<std::string, double>> analysis_results(const AnalysisSpec& a, const World& w);

// The unit of each of them, in the same order: "J" (kinetic_energy), "m" (deposit_height),
// "" for fractions, coordination numbers and counts.
std::vector<std::string> analysis_result_units(const AnalysisSpec& a);


}  // namespace tsubu
