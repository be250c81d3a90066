// What a run records as it goes (docs/cli.md, output folder): a series.csv row every series
// interval, with the analyses' values (each row first checks the energies, and is the one
// that may meet a [[stop]] condition); track rows and VTK frames at their intervals; rows
// reach the files at least every second.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "tsubu/analysis/energy_watch.hpp"
#include "tsubu/analysis/monitor.hpp"
#include "tsubu/app/checkpoint.hpp"
#include "tsubu/app/run_clock.hpp"
#include "tsubu/app/run_files.hpp"
#include "tsubu/app/runner.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu {

class RunObservers {
 public:
  // `from`: the checkpoint a resume continues from (the files are cut back to it, the energy
  // check goes on from its reference), or null for a fresh run.
  RunObservers(const Scenario& sc, const Simulation& sim, const std::filesystem::path& out_dir, const Checkpoint* from);

  // A fresh run, after Simulation::start: the rows and the frame of step 0.
  void first_rows(const Simulation& sim);
  // A resumed run: one that a [[stop]] condition ended at its checkpoint stays ended.
  void resumed(const Simulation& sim);
  // After step `step` of a run that ends at `last_step`: the rows and frames due (the last
  // step's, or the one a [[stop]] condition ends, writes them all). Returns whether the run
  // ends here.
  bool after_step(Simulation& sim, std::int64_t step, std::int64_t last_step);
  // The grains gone through an open face since the last call, as outflow.csv rows (after
  // every step, and before a failure is recorded).
  void departures(Simulation& sim);
  // Whether after_step reads the state at `step` (writes a row or a frame).
  bool reads_state(std::int64_t step, std::int64_t last_step) const {
    return step == last_step || step % series_every_ == 0 || step % track_every_ == 0 || (vtk_every_ && step % vtk_every_ == 0);
  }
  // The [[stop]] condition that ended the run ("" while none has).
  const std::string& stop_reason() const { return stop_reason_; }
  // Where the [[stop]] conditions stand, for the progress report.
  std::string stop_progress(const Simulation& sim) const;

  // The rows written so far reach the files (flushed, not synced), now or when a second has
  // passed since they last did.
  void flush(const RunClock& clock);
  void flush_if_due(const RunClock& clock);
  // A checkpoint of the state now: the energies must be finite; the rows it refers to are
  // flushed; it records the files' sizes and the energy check (`sync` puts them on disk).
  void prepare_checkpoint(const Simulation& sim, const RunClock& clock, Checkpoint& c);
  void sync() { files_.sync(); }
  // A last frame of a failing state, for a look at what went wrong.
  void failure_frame(const Simulation& sim) { files_.frame(sim); }
  void close() { files_.close(); }
  // A completed run's results: the analyses' values at the end, the inflow's rates and
  // counts, each with its unit, in the scenario's order; the sources' grain sizes.
  void add_results(const Simulation& sim, RunSummary& summary);

 private:
  const Scenario& sc_;
  std::int64_t series_every_, track_every_, vtk_every_;  // steps; vtk 0: no frames but the first
  AnalysisMonitor monitor_;
  RunFiles files_;
  EnergyWatch energy_watch_;
  std::string stop_reason_;
  double last_flush_ = 0;  // the session's seconds when rows last reached the files

  void series_row(const Simulation& sim);
  bool inflow_ended(const Simulation& sim) const { return sim.inflow() && sim.inflow()->ended(); }
};

}  // namespace tsubu
