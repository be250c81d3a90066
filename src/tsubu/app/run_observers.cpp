#include "tsubu/app/run_observers.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "tsubu/analysis/grain_sizes.hpp"
#include "tsubu/analysis/measures.hpp"
#include "tsubu/analysis/results.hpp"

namespace tsubu {

namespace {

// Steps between outputs; an interval longer than any run (1e300 meaning "never") is capped
// so that only the first and last step write.
std::int64_t every(double interval, double dt) {
  return std::max<std::int64_t>(1, std::llround(std::min(interval / dt, 0x1p62)));
}

}  // namespace

RunObservers::RunObservers(const Scenario& sc, const Simulation& sim, const std::filesystem::path& out_dir,
                           const Checkpoint* from)
    : sc_(sc),
      series_every_(every(sc.output.series_interval, sc.dt)),
      track_every_(every(sc.output.track_interval, sc.dt)),
      vtk_every_(sc.output.vtk_interval > 0 ? every(sc.output.vtk_interval, sc.dt) : 0),
      monitor_(sc.analyses, sc.stops),
      files_(sc, sim, out_dir, monitor_.names(), from),
      // Entering grains bring energy: no energy-growth check with an inflow or insertion (the
      // scenario's, which a split run's observed state is fed only at its first gathering).
      energy_watch_(sim.world(), sim.model(), inflow_source(sc) ? 0.0 : sc.energy_growth_limit) {
  if (from) energy_watch_.restore(from->energy_watch);
}

void RunObservers::series_row(const Simulation& sim) {
  const World& world = sim.world();
  const Energies e = energies(world, sim.model().gravity);
  const ContactTotals c = sim.forces().totals(world);
  energy_watch_.observe(world, c.elastic_energy);  // before the row: a failing state is not written
  const std::vector<double>& results = monitor_.evaluate(world);  // before it too: a signal may cut it short
  files_.series_row(sim, e, c, results);
  stop_reason_ = monitor_.stop_reason(inflow_ended(sim));
}

void RunObservers::first_rows(const Simulation& sim) {
  series_row(sim);
  files_.track_rows(sim.world());
  if (vtk_every_) files_.frame(sim);
}

void RunObservers::resumed(const Simulation& sim) {
  if (sim.world().step % series_every_ != 0) return;  // the checkpoint's step wrote no row
  monitor_.evaluate(sim.world());
  stop_reason_ = monitor_.stop_reason(inflow_ended(sim));
}

void RunObservers::departures(Simulation& sim) {
  if (Outflow* outflow = sim.outflow()) files_.departure_rows(outflow->take_departures());
}

bool RunObservers::after_step(Simulation& sim, std::int64_t step, std::int64_t last_step) {
  departures(sim);
  if (step % series_every_ == 0 || step == last_step) series_row(sim);
  const bool last = step == last_step || !stop_reason_.empty();
  if (step % track_every_ == 0 || last) files_.track_rows(sim.world());
  if (vtk_every_ && (step % vtk_every_ == 0 || last)) files_.frame(sim);
  return last;
}

std::string RunObservers::stop_progress(const Simulation& sim) const { return monitor_.stop_progress(inflow_ended(sim)); }

void RunObservers::flush(const RunClock& clock) {
  files_.flush();
  last_flush_ = clock.elapsed();
}

void RunObservers::flush_if_due(const RunClock& clock) {
  if (clock.elapsed() - last_flush_ >= 1.0) flush(clock);
}

void RunObservers::prepare_checkpoint(const Simulation& sim, const RunClock& clock, Checkpoint& c) {
  const World& world = sim.world();
  require_finite_energies(world, sim.model().gravity, sim.forces().totals(world).elastic_energy);  // only good states are kept
  flush(clock);
  c.energy_watch = energy_watch_.state();
  c.output = files_.state();
}

void RunObservers::add_results(const Simulation& sim, RunSummary& summary) {
  const World& world = sim.world();
  const std::vector<double>& values = monitor_.evaluate(world);
  for (std::size_t k = 0; k < values.size(); ++k) summary.results[monitor_.names()[k]] = values[k];
  for (const AnalysisSpec& a : sc_.analyses)
    for (const std::string& unit : analysis_result_units(a)) summary.result_units.push_back(unit);
  summary.result_order = monitor_.names();
  if (const InflowFeed* inflow = sim.inflow())
    for (const auto& [name, value] : inflow->results(world.time, sim.inflow_mass_entered())) {
      summary.results[name] = value;
      summary.result_order.push_back(name);
      summary.result_units.push_back(inflow_result_unit(name));
    }
  if (const Outflow* outflow = sim.outflow()) {
    const Outflow::Totals& t = outflow->totals();
    for (const auto& [name, value, unit] : {std::tuple("outflow_count", static_cast<double>(t.count), ""),
                                            std::tuple("outflow_mass", t.mass, "kg")}) {
      summary.results[name] = value;
      summary.result_order.push_back(name);
      summary.result_units.push_back(unit);
    }
  }
  summary.sources = source_sizes(world);
}

}  // namespace tsubu
