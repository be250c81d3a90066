#include "tsubu/app/observed_run.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "tsubu/core/error.hpp"
#include "tsubu/core/stop_signal.hpp"
#include "tsubu/ranks/shared_block_steps.hpp"
#include "tsubu/scenario/result_names.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

void refuse_what_cannot_split(const Scenario& sc, int processes) {
  if (!RankGrid::fits(sc.parallel.counts, processes)) {
    const auto& c = sc.parallel.counts;
    throw InputError(sc.parallel.where, "no grid of " + std::to_string(processes) + " subdomains (mpirun -np " +
                                            std::to_string(processes) + ") has " + std::to_string(c[0]) + " x " +
                                            std::to_string(c[1]) + " x " + std::to_string(c[2]) +
                                            ": give counts whose product is the number of processes, 0 along an axis for "
                                            "an automatic count, or start as many processes as the counts make");
  }
  if (const int seen = Communicator::world().size(); seen != processes)
    throw UsageError("started as " + std::to_string(processes) + " processes, but this tsubu sees " +
                     std::to_string(seen) + " (built without MPI, or its MPI is not the launcher's): run one "
                     "process, or build tsubu with the launcher's MPI (docs/parallel.md)");
}

ObservedRun::ObservedRun(const Scenario& sc, Simulation& sim) : part_(sim) {
  const Communicator& comm = Communicator::world();
  writes_ = comm.rank() == 0;
  if (sim.block()) {
    share_ = share_block_steps(comm, sim);
    return;
  }
  if (writes_) {
    mirror_.emplace(sim.world(), build_model(sc), sc.integrator, sc.block_steps);
    mirror_->forces().restore_counters(sim.forces().counters());
  }
  decomposition_ = split_among_processes(comm, sim, sim.world().domain, sc.parallel);
}

std::unique_ptr<Decomposition> split_among_processes(const Communicator& comm, Simulation& sim, const Domain& cut,
                                                     const ParallelSpec& parallel) {
  const auto [smallest, largest] = sim.radius_range();  // the inflow's grains included
  auto d = std::make_unique<Decomposition>(comm, cut, sim.forces().skin_for(smallest), sim.forces().reach_per_radius(),
                                           largest, parallel.counts, parallel.balance);
  d->distribute(sim.world());
  sim.forces().set_neighbourhood(d.get());
  return d;
}

void ObservedRun::start() {
  part_.start();
  if (split()) gather();
}

void ObservedRun::advance() {
  gathered_current_ = false;
  if (!split()) return part_.step();
  failure_ = part_.step_to_its_end();
  if (!mirror_) return;
  mirror_->world().step = part_.world().step;
  mirror_->world().time = part_.world().time;
}

int ObservedRun::agree_after_step(bool wanted) {
  if (!split()) return g_stop_signal;
  // One reduction for all three: the largest of kFailed where a process's force check failed
  // (or the step was abandoned: a process's drift lost a particle), else 2 x its signal
  // number, or 1 where a process wants the state and has no signal (the numbers are small:
  // exact in a double). A failure ends the run, whatever the signals.
  constexpr double kFailed = 1e6;
  const double word = Communicator::world().max(failure_ ? kFailed
                                                : g_stop_signal != 0 ? 2.0 * g_stop_signal
                                                : wanted ? 1.0 : 0.0);
  unread_step_ = word == 0;
  if (word > 0) gather();
  if (word == kFailed) {
    const std::exception_ptr mine = std::exchange(failure_, nullptr);
    if (mine && (decomposition_ || writes_)) {  // with block steps every process failed alike: process 0 says it
      try {
        std::rethrow_exception(mine);
      } catch (const StepAbandoned&) {  // not this process's failure: as below
      }
    }
    failed_elsewhere_ = true;
    return 0;
  }
  return static_cast<int>(word / 2);
}

void ObservedRun::await_failure() {
  Communicator::world().any(false);  // the failed process never joins: its message arrives meanwhile
  throw std::logic_error("a split run's failed process did not report its failure");
}

bool ObservedRun::agree_last(bool last) {
  if (!split()) return last;
  if (unread_step_) {
    unread_step_ = false;
    if (last && writes())
      throw std::logic_error("process 0 ended a split run at a step whose state it had not gathered");
    return false;
  }
  return Communicator::world().any(last && writes());
}

void ObservedRun::gather() {
  gathered_current_ = true;
  if (!decomposition_) {  // block steps: every process holds the whole run
    if (Outflow* outflow = part_.outflow(); outflow && !writes_) outflow->take_departures();
    return;
  }
  Decomposition::Gathered all = decomposition_->gathered(part_.world(), part_.forces());
  Outflow* outflow = part_.outflow();  // every process's records every departure
  if (!mirror_) {
    if (outflow) outflow->take_departures();  // process 0's are written
    return;
  }
  if (outflow) mirror_->outflow()->follow(*outflow);
  loads_ = std::move(all.loads);
  mirror_->world() = std::move(all.world);
  if (const InflowFeed* inflow = part_.inflow()) mirror_->feed(*inflow);  // every process's stream is alike
  mirror_->forces().adopt_results(std::move(all.pair_results), std::move(all.wall_results));
  mirror_->forces().restore_counters(part_.forces().counters());  // this process's work
}

}  // namespace tsubu
