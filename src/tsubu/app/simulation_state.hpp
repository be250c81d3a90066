// A Simulation's state in a Checkpoint and back, for every driver: the command line's
// checkpoints and resumes (app/runner.cpp) and the Python binding's (python/).
#pragma once
#include <filesystem>
#include <functional>
#include <optional>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/inflow_feed.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu {

// The run into c: this engine's version, the scenario (text, file, overrides, hash), sim's
// clock, force counters, walls and block-step state, and the inflow's stream (if any). The
// particles and contact lists are not copied (with_state_lent); the driver adds its own
// (run id, outputs, energy watch).
void store_simulation(const Scenario& sc, const Simulation& sim, Checkpoint& c);

// A fresh run of sc, not yet started: the world its sources make, its model, and its inflow
// (if any) fed in.
Simulation new_simulation(const Scenario& sc);

// Runs `write` with sim's particles and contact lists lent to c (moved in, not copied: a copy
// of a large run's state would double its peak memory) and given back whatever happens.
void with_state_lent(Simulation& sim, Checkpoint& c, const std::function<void()>& write);

// Which checkpoint read_newest_checkpoint takes, and what it does with a damaged one.
struct CheckpointChoice {
  const char* purpose = "resume";  // the command, for messages ("nothing to resume")
  std::optional<double> at;        // s: the newest at or before this time (tsubu export --at)
  bool rename_damaged = true;      // false: leave a damaged file where it is (tsubu export)
};

// The newest checkpoint of dir that reads back (step_*.tsbk, newest first) and is at or
// before choice.at; unusable ones are reported on stderr and renamed to *.damaged (out of the
// way of the run's next checkpoints) or skipped. Sets `used` to its file. Throws
// std::runtime_error when dir holds no valid checkpoint, UsageError when every valid one is
// later than choice.at (naming their times).
Checkpoint read_newest_checkpoint(const std::filesystem::path& dir, std::filesystem::path& used,
                                  const CheckpointChoice& choice = {});

// The scenario a checkpoint stores (with its overrides), checked against its hash and dt.
Scenario scenario_of(const Checkpoint& c, const std::filesystem::path& used);

// The Simulation of checkpoint c (file `used`, for messages) under scenario sc, taking c's
// particles and contact lists, with the scenario's inflow fed in where it stood. Fixed
// steps: the lists are rebuilt from the stored contacts at the next step and the forces are
// those stored (not recomputed). Block steps: the lists as they were, from the stored build
// positions.
Simulation restore_simulation(const Scenario& sc, Checkpoint& c, const std::filesystem::path& used);

}  // namespace tsubu
