// The run the observers of app/runner.cpp read (docs/parallel.md, "From the command line"):
// one process's Simulation itself, or, for a run split among the processes an MPI launcher
// started, a mirror on process 0 that holds the whole state gathered from every process on
// the steps where something reads it (outputs, checkpoints, the progress report); with the
// decisions every process must share, taken collectively after each step. Block steps are
// not split: every process holds the whole run and shares out the active particles
// (BlockHermite::share_among), and process 0 writes from its own copy.
#pragma once
#include <array>
#include <cstdint>
#include <exception>
#include <memory>
#include <optional>

#include "tsubu/integrate/active_share.hpp"
#include "tsubu/ranks/decomposition.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu {

class ObservedRun {
 public:
  // One process: the observers read `sim` itself.
  explicit ObservedRun(Simulation& sim) : part_(sim) {}
  // `sim`, the whole run on every process (built from the scenario or restored from a whole
  // checkpoint), split among MPI's processes (refuse_what_cannot_split first): each keeps its
  // part, and process 0 a copy of the whole as the mirror; with block steps each keeps the
  // whole and evaluates its share of the active particles.
  ObservedRun(const Scenario& sc, Simulation& sim);

  // Started as several processes: a split run, or block steps sharing out their active particles.
  bool split() const { return decomposition_ != nullptr || share_ != nullptr; }
  // Process 0 (or the one process): the process that writes the run's files.
  bool writes() const { return writes_; }
  // What the observers read (process 0): the whole state as of the last gather, at the step
  // and time of the last step.
  Simulation& observed() { return mirror_ ? *mirror_ : part_; }

  // A fresh run's first evaluation (Simulation::start), gathered.
  void start();
  // One step of this process's part (a failed force check is thrown at the step's end; in a
  // split run it is kept for agree_after_step).
  void advance();
  // After a step: whether something on process 0 reads the state now (`wanted`, process 0's
  // say), a stop signal arrived on any process, or a process's force check failed; the whole
  // state is then gathered, and a process whose check failed throws its NumericalError.
  // Returns the signal (0: none).
  int agree_after_step(bool wanted);
  // Process 0 of a split run, after agree_after_step: another process's force check failed
  // at this step (the whole failing state is gathered; its message comes with await_failure).
  bool failed_elsewhere() const { return failed_elsewhere_; }
  // Waits for the failed process's message, which ends the run (ProcessFailed).
  [[noreturn]] void await_failure();
  // Whether observed() holds the state of this process's last step: always for one process;
  // in a split run, when it was gathered after that step (not after a failure inside it).
  bool observed_is_current() const { return !split() || gathered_current_; }
  // Whether the run ends here, as process 0 says. After a step whose state no one read
  // (agree_after_step gathered nothing) process 0 cannot say so: its observers read the state
  // at the last step and wherever a [[stop]] condition is evaluated. Every process then knows
  // the answer, no, without asking (throws std::logic_error should process 0 say yes).
  bool agree_last(bool last);
  // Process 0 of a split run: the grid of subdomains, and what each process held and had
  // sent at the last gather (run.json "processes"); empty otherwise.
  std::vector<ProcessLoad> loads() const { return loads_; }
  const RankGrid* grid() const { return decomposition_ ? &decomposition_->grid() : nullptr; }

 private:
  Simulation& part_;
  std::unique_ptr<Decomposition> decomposition_;  // fixed steps: each process holds its subdomain
  std::unique_ptr<ActiveShare> share_;            // block steps: each holds the whole run (docs/parallel.md)
  bool writes_ = true;
  std::optional<Simulation> mirror_;  // process 0 of a split run
  std::vector<ProcessLoad> loads_;    // of the last gather, on process 0
  bool unread_step_ = false;          // the last agree_after_step gathered nothing
  std::exception_ptr failure_;        // this process's failed force check, until agree_after_step
  bool failed_elsewhere_ = false;
  bool gathered_current_ = false;     // gathered since the last advance() began

  void gather();
};

// Splits `sim`, the whole run on every process, among comm's processes on a grid of `cut`
// (the run's box, or for tests a part of it) as `parallel` says (RankGrid): each keeps its part,
// and sim's force field reads the others' particles through the Decomposition returned,
// which must outlive it. The ghost layer and the hand-overs follow from the particles' and
// the inflow's smallest and largest grains.
std::unique_ptr<Decomposition> split_among_processes(const Communicator& comm, Simulation& sim, const Domain& cut,
                                                     const ParallelSpec& parallel);

// A run among the `processes` processes a launcher started is refused (UsageError) when the
// processes are not one MPI job (a build without MPI); an InputError when no grid of that
// many subdomains has the scenario's parallel.counts. Starts MPI.
void refuse_what_cannot_split(const Scenario& sc, int processes);

}  // namespace tsubu
