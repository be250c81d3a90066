// The run's [[analyses]] on the current state, evaluated at every series.csv row (one column
// per result), for run.json's results at the end, and the [[stop]] conditions that watch them
// (docs/scenario.md, [[analyses]] and [[stop]]).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

class AnalysisMonitor {
 public:
  AnalysisMonitor(std::vector<AnalysisSpec> analyses, std::vector<StopSpec> stops);

  // The result names, in the order of the analyses and of analysis_results.
  const std::vector<std::string>& names() const { return names_; }
  // Every analysis on w's state; evaluated once per step (a second call at the same step
  // returns the values it has).
  const std::vector<double>& evaluate(const World& w);
  // The first [[stop]] condition that the values of the step last evaluated meet, as a
  // sentence ("deposit_height = 0.016 >= 0.016 at t = 1.2 s"); empty when none does.
  // `inflow_ended`: the inflow has released its last grain (conditions with after_inflow).
  std::string stop_reason(bool inflow_ended) const;
  // Where each [[stop]] condition stands, for the progress report: "speed_rms <= 0.001: now
  // 0.05", with "(checked from t = 0.5 s)" or "(checked after the inflow's last grain)" while
  // that holds; "; " between conditions, empty without any.
  std::string stop_progress(bool inflow_ended) const;

 private:
  std::vector<AnalysisSpec> analyses_;
  std::vector<StopSpec> stops_;
  std::vector<std::string> names_;
  std::vector<std::size_t> stop_index_;  // the result each stop watches
  std::vector<double> values_;
  std::int64_t step_ = -1;  // of values_
  double time_ = 0;
};

}  // namespace tsubu
