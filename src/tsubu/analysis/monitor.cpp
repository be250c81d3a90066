#include "tsubu/analysis/monitor.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tsubu/analysis/results.hpp"

namespace tsubu {

AnalysisMonitor::AnalysisMonitor(std::vector<AnalysisSpec> analyses, std::vector<StopSpec> stops)
    : analyses_(std::move(analyses)), stops_(std::move(stops)) {
  for (const AnalysisSpec& a : analyses_)
    for (std::string& name : analysis_result_names(a)) names_.push_back(std::move(name));
  for (const StopSpec& s : stops_)  // the loader checked that every stop names a result
    stop_index_.push_back(static_cast<std::size_t>(std::find(names_.begin(), names_.end(), s.when) - names_.begin()));
}

const std::vector<double>& AnalysisMonitor::evaluate(const World& w) {
  if (w.step == step_) return values_;
  values_.clear();
  for (const AnalysisSpec& a : analyses_)
    for (const auto& [name, value] : analysis_results(a, w)) values_.push_back(value);
  step_ = w.step;
  time_ = w.time;
  return values_;
}

std::string AnalysisMonitor::stop_reason(bool inflow_ended) const {
  if (step_ < 0) return "";
  for (std::size_t k = 0; k < stops_.size(); ++k) {
    const StopSpec& s = stops_[k];
    const double v = values_[stop_index_[k]];
    // A relative 1e-12 of slack: a deposit height of 4 slices of 0.1 L reaches 0.4 L
    // whatever the round-off of 4 * (0.1 * L).
    const double slack = 1e-12 * std::abs(s.limit);
    if (time_ < s.after || (s.after_inflow && !inflow_ended) || !(s.at_least ? v >= s.limit - slack : v <= s.limit + slack)) continue;
    std::ostringstream out;
    out.precision(9);
    out << s.when << " = " << v << (s.at_least ? " >= " : " <= ") << s.limit << " at t = " << time_ << " s";
    return out.str();
  }
  return "";
}

std::string AnalysisMonitor::stop_progress(bool inflow_ended) const {
  std::ostringstream out;
  out.precision(4);
  for (std::size_t k = 0; k < stops_.size(); ++k) {
    const StopSpec& s = stops_[k];
    out << (k > 0 ? "; " : "") << s.when << (s.at_least ? " >= " : " <= ") << s.limit << ": now ";
    if (step_ < 0) out << "?";
    else out << values_[stop_index_[k]];
    if (time_ < s.after) out << " (checked from t = " << s.after << " s)";
    else if (s.after_inflow && !inflow_ended) out << " (checked after the inflow's last grain)";
  }
  return out.str();
}

}  // namespace tsubu
