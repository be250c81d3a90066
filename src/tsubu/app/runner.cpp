#include "tsubu/app/runner.hpp"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/app/observed_run.hpp"
#include "tsubu/app/progress.hpp"
#include "tsubu/app/resume_rules.hpp"
#include "tsubu/app/run_checkpoints.hpp"
#include "tsubu/app/run_clock.hpp"
#include "tsubu/app/run_observers.hpp"
#include "tsubu/app/run_json.hpp"
#include "tsubu/app/simulation_state.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/core/stop_signal.hpp"
#include "tsubu/io/output_dir.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu/sim/time_scales.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/version.hpp"

namespace tsubu {

namespace {

extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

// SIGINT and SIGTERM ask the loop to stop after the current step with a final checkpoint;
// a second one acts as usual (SA_RESETHAND). The previous handlers return afterwards.
class StopSignals {
 public:
  StopSignals() {
    reset_stop_signal();
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// A run's summary as it stands: steps, particles, wall time, the force field's and the
// integrator's counters, the stepping loops' totals, a split run's grid and loads (results
// are added at a completed end).
RunSummary summarise(const ObservedRun& run, const Simulation& sim, const RunClock& clock) {
  RunSummary summary;
  if (const RankGrid* grid = run.grid()) {
    for (int a = 0; a < 3; ++a) summary.cuts[static_cast<std::size_t>(a)] = grid->cuts(a);
    summary.processes = run.loads();
  }
  summary.steps = sim.world().step;
  summary.particles = sim.world().particles.size();
  summary.wall_seconds = clock.wall_seconds();
  summary.contact_evaluations = sim.forces().evaluations();
  summary.list_builds = sim.forces().rebuilds();
  summary.particle_force_evaluations = sim.particle_force_evaluations();
  if (const BlockHermite* b = sim.block()) summary.block_steps = b->stats();
  const Checkpoint::Record r = clock.record(sim.world());
  summary.loop_steps = r.loop_steps;
  summary.loop_seconds = r.loop_seconds;
  summary.loop_sessions = r.loop_sessions;
  return summary;
}

// How a signal stopped the run, and how to continue it.
std::string stopped_message(int sig, const World& world, const RunCheckpoints& checkpoints, const std::string& out_dir) {
  std::ostringstream msg;
  msg << "stopped by " << (sig == SIGINT ? "SIGINT" : "SIGTERM") << " after step " << world.step << " (t = " << world.time
      << " s); " << (checkpoints.newest_step() == world.step ? "a checkpoint of this step is" : "the newest checkpoint is")
      << " in " << checkpoints.dir().string() << ": `tsubu resume " << out_dir << "` continues the run";
  return msg.str();
}

// A signal during a long analysis: the step's outputs are not written, so this step cannot
// be checkpointed; the newest checkpoint stays the last one.
std::string cut_short_message(int sig, const World& world, const RunCheckpoints& checkpoints, const std::string& out_dir) {
  std::ostringstream msg;
  msg << "stopped by " << (sig == SIGINT ? "SIGINT" : "SIGTERM") << " during the analyses of step " << world.step
      << " (t = " << world.time << " s), whose outputs are not written; "
      << (checkpoints.newest_step() < 0 ? "no checkpoint was written before: run again"
                                        : "the newest checkpoint (step " + std::to_string(checkpoints.newest_step()) +
                                              ") is in " + checkpoints.dir().string() + ": `tsubu resume " + out_dir +
                                              "` continues the run");
  return msg.str();
}

// The time loop from the run's state, on the process that writes the files: from step 0
// (from == nullptr; forces not yet computed) or from a checkpoint whose world state, forces
// included, is already in the run. The observers read run.observed(); the other processes of
// a split run follow (follow()), taking the same collective decisions after every step.
RunSummary execute(const Scenario& sc, ObservedRun& run, const std::string& out_dir, const std::string& run_id,
                   int threads, bool progress, const Checkpoint* from) {
  Simulation& sim = run.observed();
  const World& world = sim.world();
  RunObservers observers(sc, sim, out_dir, from);
  RunCheckpoints checkpoints(sc, out_dir, from);
  RunClock clock(from);
  const std::string json = (std::filesystem::path(out_dir) / "run.json").string();
  auto end_with = [&](const char* status, const std::string& message) {
    write_run_json(json, run_id, sc, threads, summarise(run, sim, clock), status, message);
  };
  // A failure: the outputs so far flushed, run.json `failed` with its message and the last
  // good checkpoint named; returns that message.
  auto failed = [&](const std::string& what) {
    observers.departures(sim);
    observers.flush(clock);
    const std::string msg = what + checkpoints.kept();
    end_with("failed", msg);
    return msg;
  };
  // Everything after a completed step, its outputs on disk first.
  auto checkpoint = [&] {
    Checkpoint c;
    observers.prepare_checkpoint(sim, clock, c);
    store_simulation(sc, sim, c);
    c.run_id = run_id;
    c.record = clock.record(world);
    c.wall_seconds = clock.wall_seconds();
    checkpoints.write(sim, c, [&] { observers.sync(); }, clock);
  };
  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  const Progress::Mode mode = progress_mode(progress);
  const double log_interval = mode == Progress::Mode::log ? progress_log_interval() : 0.0;
  StopSignals stop_signals;
  bool deciding = true;  // the other processes of a split run wait in agree_last for this one's word
  try {
    if (from) {
      observers.resumed(sim);
    } else {
      run.start();
      observers.first_rows(sim);
    }
    Progress report(mode, log_interval, world.step, steps, clock.elapsed());
    auto physics = [&] {
      const Energies e = energies(world, sim.model().gravity);
      return ProgressPhysics{e.kinetic_translational + e.kinetic_rotational, sim.forces().totals(world).contacts};
    };
    clock.loop_starts(world.step);
    for (bool last = run.agree_last(world.step >= steps || !observers.stop_reason().empty()); !last;) {
      deciding = false;
      run.advance();
      clock.stepped(world.step);
      const bool checkpoint_due = checkpoints.due(world.step, clock);
      const bool report_due = report.active() && report.due(clock.elapsed());
      const int sig = run.agree_after_step(observers.reads_state(world.step, steps) || checkpoint_due || report_due);
      if (run.failed_elsewhere()) {  // another process's force check failed: the state it failed in, then its message
        observers.failure_frame(sim);
        run.await_failure();
      }
      deciding = true;
      last = run.agree_last(observers.after_step(sim, world.step, steps));
      deciding = false;
      if (sig != 0) {
        checkpoint();
        const std::string msg = stopped_message(sig, world, checkpoints, out_dir);
        end_with("interrupted", msg);
        throw Interrupted(msg);
      }
      if (!last && checkpoint_due) checkpoint();
      else observers.flush_if_due(clock);
      if (report_due) report.report(world.step, world.time, clock.elapsed(), physics, observers.stop_progress(sim));
    }
    report.finish();
    if (checkpoints.enabled() && checkpoints.newest_step() != world.step) checkpoint();  // the final state
    observers.close();
  } catch (const StopRequested&) {
    if (deciding) run.agree_last(true);  // the other processes end too, at this step
    observers.flush(clock);
    const std::string msg = cut_short_message(g_stop_signal, world, checkpoints, out_dir);
    end_with("interrupted", msg);
    throw Interrupted(msg);
  } catch (const NumericalError& e) {
    // Nothing of the failing state goes into a checkpoint: the last good one stays. Its frame
    // is written where the whole failing state is at hand (in a split run, gathered after a
    // failed force check or where the observers read it; not after a failure inside a step).
    if (run.observed_is_current()) observers.failure_frame(sim);
    throw NumericalError(failed(e.what()));
  } catch (const ProcessFailed& e) {  // another process of a split run failed
    throw ProcessFailed(e.process, e.code, e.kind, failed(e.what()));
  } catch (const WriteError& e) {
    const std::string msg = e.what() + checkpoints.kept();
    try {
      end_with("failed", msg);
    } catch (const WriteError&) {  // the disk that refused the output may refuse this too
    }
    throw WriteError(msg);
  }
  RunSummary summary = summarise(run, sim, clock);
  observers.add_results(sim, summary);
  summary.stop_reason = observers.stop_reason().empty() ? "duration" : observers.stop_reason();
  write_run_json(json, run_id, sc, threads, summary, "ok", "");
  return summary;
}

// A process of a split run other than process 0: its part of execute()'s loop, with the same
// collective steps in the same order, until process 0 says the run ends (or a stop signal:
// process 0 writes the checkpoint).
void follow(ObservedRun& run, bool fresh) {
  StopSignals stop_signals;
  if (fresh) run.start();
  for (bool last = run.agree_last(false); !last;) {
    run.advance();
    const int sig = run.agree_after_step(false);
    last = run.agree_last(false) || sig != 0;
  }
}

// Block steps on several processes give one process's bits, not its speed (docs/parallel.md,
// "Block steps on several processes"): said once, by process 0.
void warn_of_shared_block_steps(const Scenario& sc, const Processes& processes) {
  if (processes.count > 1 && sc.integrator == Integrator::block_hermite)
    std::fprintf(stderr,
                 "tsubu: WARNING: block steps on %d processes: each holds the whole run and evaluates its share of "
                 "the active grains at every block time, which is slower than one process (1.3-1.7 times on 2 "
                 "processes, docs/parallel.md); for speed run block steps as one process, with --threads\n",
                 processes.count);
}

// The scenario checkpoint c (file `used`) stores, with a resume's --set values.
Scenario resumed_scenario(const Checkpoint& c, const std::filesystem::path& used, const std::vector<std::string>& sets) {
  const Scenario stored = scenario_of(c, used);
  return sets.empty() ? stored : with_resume_overrides(stored, sets, c.step);
}

}  // namespace

RunSummary run_scenario(const Scenario& sc, const std::string& out_dir, int threads, bool progress, bool overwrite,
                        const Processes& processes) {
  if (processes.count > 1) refuse_what_cannot_split(sc, processes.count);
  Simulation sim = new_simulation(sc);  // bad input is reported before the folder is touched
  if (processes.rank != 0) {
    ObservedRun run(sc, sim);
    follow(run, true);
    return {};
  }
  for (const std::string& w : time_scales(sc, sim.world()).warnings) std::fprintf(stderr, "tsubu: WARNING: %s\n", w.c_str());
  warn_of_shared_block_steps(sc, processes);
  const OutputDir owner = OutputDir::claim_new(out_dir, overwrite);
  ObservedRun run = processes.count > 1 ? ObservedRun(sc, sim) : ObservedRun(sim);
  return execute(sc, run, out_dir, owner.run_id(), threads, progress, nullptr);
}

RunSummary resume_run(const std::string& out_dir, int threads, bool progress, const std::vector<std::string>& sets,
                      const Processes& processes) {
  namespace fs = std::filesystem;
  if (processes.rank != 0) {  // reads the checkpoint process 0 takes (which checks it against the folder) and follows
    fs::path used;
    Checkpoint c = read_newest_checkpoint(fs::path(out_dir) / "checkpoint", used, {"resume", std::nullopt, false});
    const Scenario sc = resumed_scenario(c, used, sets);
    refuse_what_cannot_split(sc, processes.count);
    Simulation sim = restore_simulation(sc, c, used);
    ObservedRun run(sc, sim);
    follow(run, false);
    return {};
  }
  const OutputDir owner = OutputDir::claim_existing(out_dir);
  fs::path used;
  Checkpoint c = read_newest_checkpoint(fs::path(out_dir) / "checkpoint", used);
  if (c.run_id != owner.run_id())
    throw std::runtime_error(used.string() + " belongs to run " + (c.run_id.empty() ? "?" : c.run_id) + ", but " + out_dir +
                             (owner.run_id().empty() ? " has no " + std::string(kRunMarker) + " naming its run"
                                                     : " holds the outputs of run " + owner.run_id()) +
                             ": a resume continues only the run whose outputs are in the folder");
  if (c.engine_version != kVersion)
    std::fprintf(stderr, "tsubu: warning: %s was written by tsubu %s, this is %s: the continuation may differ from an uninterrupted run\n",
                 used.string().c_str(), c.engine_version.c_str(), kVersion);
  const Scenario sc = resumed_scenario(c, used, sets);
  if (processes.count > 1) refuse_what_cannot_split(sc, processes.count);
  warn_of_shared_block_steps(sc, processes);
  refuse_losing_rows(sc, c, used, out_dir);
  Simulation sim = restore_simulation(sc, c, used);
  std::fprintf(stderr, "tsubu: resuming %s from %s (step %lld, t = %.9g s)\n", sc.name.c_str(), used.string().c_str(),
               static_cast<long long>(c.step), c.time);
  ObservedRun run = processes.count > 1 ? ObservedRun(sc, sim) : ObservedRun(sim);
  return execute(sc, run, out_dir, owner.run_id(), threads, progress, &c);
}

}  // namespace tsubu
