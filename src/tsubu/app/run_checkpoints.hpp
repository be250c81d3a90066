// A run's checkpoints (docs/reliability.md): when they are due, every so many steps and/or
// seconds of wall time; written only of a completed step whose outputs are on disk; and what
// a failure's message says of the newest one.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/app/run_clock.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu {

class RunCheckpoints {
 public:
  // `from`: the checkpoint a resume continues from, or null for a fresh run. A resumed run
  // continues from checkpoints and ends with one even when its --set turned the periodic
  // ones off: a later resume from an older one would cut its outputs back. When the run
  // writes any, the folder is made here, with the scenario as run (a fresh run's; the
  // checkpoints hold their own copy) and the overrides of the run and its resumes, for people.
  RunCheckpoints(const Scenario& sc, const std::filesystem::path& out_dir, const Checkpoint* from);

  // Whether this run writes any.
  bool enabled() const { return enabled_; }
  // A periodic checkpoint is due after step `step`.
  bool due(std::int64_t step, const RunClock& clock) const;
  // Writes `c` (the driver's part filled in) with sim's state lent to it, after `sync` has put
  // every output it refers to on disk. A checkpoint that cannot be written is reported on
  // stderr and the run goes on: a run is worth more than its checkpoint.
  void write(Simulation& sim, Checkpoint& c, const std::function<void()>& sync, const RunClock& clock);
  // The step of the newest checkpoint (the one a resume started from), -1 for none.
  std::int64_t newest_step() const { return newest_step_; }
  const std::filesystem::path& dir() const { return dir_; }
  // The end of a failure's message: the last good checkpoint is kept, or there is none.
  std::string kept() const;

 private:
  std::filesystem::path dir_;
  std::int64_t every_steps_;
  double every_seconds_;
  bool enabled_, fresh_;
  std::int64_t newest_step_;
  double last_ = 0;  // the session's seconds when the last checkpoint was written
};

}  // namespace tsubu
