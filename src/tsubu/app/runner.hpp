// The time loop with its observers: time series, VTK frames, progress line, run.json.
#pragma once
#include <map>
#include <string>

#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

struct RunSummary {
  std::int64_t steps = 0;
  std::size_t particles = 0;
  std::uint64_t contact_evaluations = 0;
  double wall_seconds = 0;
  std::map<std::string, double> results;
};

// Runs the scenario, writing into out_dir. Throws NumericalError (after writing run.json
// with the diagnostic and a last VTK frame) when the simulation fails.
RunSummary run_scenario(const Scenario& scenario, const std::string& out_dir, int threads, bool progress);

}  // namespace tsubu
