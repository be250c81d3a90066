// The time loop with its observers: time series, VTK frames, progress line, run.json.
#pragma once
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tsubu/analysis/grain_sizes.hpp"
#include "tsubu/ranks/decomposition.hpp"
#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

struct RunSummary {
  std::int64_t steps = 0;
  std::size_t particles = 0;
  std::uint64_t contact_evaluations = 0;
  std::uint64_t list_builds = 0;  // neighbour-list builds
  std::uint64_t particle_force_evaluations = 0;  // see Simulation::particle_force_evaluations
  std::optional<BlockStepStats> block_steps;     // block-step runs
  double wall_seconds = 0;  // all sessions
  // The stepping loops (no set-up, first evaluation, or final checkpoint), like the peers'
  // "Loop time", of loop_sessions sessions: all of a run's, but those before a resume from a
  // checkpoint of an older tsubu. Particle-steps per second come from these.
  std::int64_t loop_steps = 0;
  double loop_seconds = 0;
  std::int64_t loop_sessions = 0;
  double particle_steps_per_second() const {
    return loop_seconds > 0 ? static_cast<double>(particles) * static_cast<double>(loop_steps) / loop_seconds : 0.0;
  }
  std::map<std::string, double> results;
  std::vector<std::string> result_order;  // the results in the order of the scenario (analyses, then inflow)
  std::vector<std::string> result_units;  // of result_order's results ("" for fractions and counts)
  std::vector<SourceSizes> sources;       // per [[particles]] source: grains and D10/D50/D90 (m) at the end
  // Why a completed run ended: "duration", or the [[stop]] condition met (run.json "stop_reason").
  std::string stop_reason;
  // A run split among processes: its grid's cuts along x, y and z, and each process's load
  // (run.json "processes"); empty for one process.
  std::array<std::vector<double>, 3> cuts;
  std::vector<ProcessLoad> processes;
};

// SIGINT or SIGTERM stopped the run after writing a checkpoint and run.json (exit code 4).
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The copies of the command an MPI launcher started (mpirun -np N; docs/parallel.md): a run
// split among them. Process 0 writes the files; the others hold their parts and follow.
struct Processes {
  int count = 1, rank = 0;
};

// Runs the scenario, writing into out_dir, with checkpoints in out_dir/checkpoint as the
// scenario's [output] asks. The folder is the run's alone (io/output_dir.hpp): a folder that
// holds another run is refused unless `overwrite`, which clears it first. Throws
// NumericalError (after writing run.json with the diagnostic and a last VTK frame;
// checkpoints are left as they were) when the simulation fails, WriteError when an output
// cannot be written, and Interrupted on SIGINT/SIGTERM. Split among `processes` (a
// UsageError for what cannot be split yet); on processes other than 0 the summary is empty.
RunSummary run_scenario(const Scenario& scenario, const std::string& out_dir, int threads, bool progress,
                        bool overwrite = false, const Processes& processes = {});

// Continues the run in out_dir from its newest valid checkpoint (older ones are tried when
// the newest is damaged), with the scenario and overrides stored in the checkpoint; the
// outputs end equal to those of an uninterrupted run. The checkpoint must belong to the run
// whose outputs the folder holds (the run id of .tsubu-run). `sets` ("key=value", as --set)
// extend or change the run where that cannot change its past: the duration, the output and
// checkpoint intervals (others throw InputError); they are kept in the run's overrides.
// Split among `processes` as run_scenario: the checkpoint of any number of processes resumes on any number.
RunSummary resume_run(const std::string& out_dir, int threads, bool progress, const std::vector<std::string>& sets = {},
                      const Processes& processes = {});

}  // namespace tsubu
