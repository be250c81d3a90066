#include "tsubu/app/runner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>


#include "tsubu/analysis/energy_watch.hpp"
#include "tsubu/analysis/grain_sizes.hpp"
#include "tsubu/analysis/measures.hpp"
#include "tsubu/analysis/monitor.hpp"
#include "tsubu/analysis/results.hpp"
#include "tsubu/app/checkpoint.hpp"
#include "tsubu/app/progress.hpp"
#include "tsubu/app/run_files.hpp"
#include "tsubu/app/run_json.hpp"
#include "tsubu/app/simulation_state.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/core/format.hpp"
#include "tsubu/core/stop_signal.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu/io/output_dir.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/inflow_feed.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu/sim/time_scales.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/version.hpp"

namespace tsubu {

namespace {

// Steps between outputs; an interval longer than any run (1e300 meaning "never") is capped
// so that only the first and last step write.
std::int64_t every(double interval, double dt) {
  return std::max<std::int64_t>(1, std::llround(std::min(interval / dt, 0x1p62)));
}

// When a run writes: a series row, a track row and a frame every so many steps (vtk 0: no
// frames but the first); a checkpoint every checkpoint_steps steps and/or every
// checkpoint_seconds of wall time (0: not by that measure).
struct Cadence {
  explicit Cadence(const Scenario& sc)
      : series(every(sc.output.series_interval, sc.dt)),
        track(every(sc.output.track_interval, sc.dt)),
        vtk(sc.output.vtk_interval > 0 ? every(sc.output.vtk_interval, sc.dt) : 0),
        checkpoint_steps(sc.output.checkpoint_every_steps),
        checkpoint_seconds(sc.output.checkpoint_every_seconds) {}
  bool checkpoint_due(std::int64_t step, double seconds_since_last) const {
    return (checkpoint_steps > 0 && step % checkpoint_steps == 0) ||
           (checkpoint_seconds > 0 && seconds_since_last >= checkpoint_seconds);
  }
  std::int64_t series, track, vtk, checkpoint_steps;
  double checkpoint_seconds;
};

// The checkpoint folder, for people: the scenario as run (the checkpoints hold their own
// copy; written by a fresh run) with the overrides of the run and of its resumes.
void prepare_checkpoint_folder(const std::filesystem::path& dir, const Scenario& sc, bool fresh) {
  std::filesystem::create_directories(dir);
  if (fresh) write_file_atomically(dir / "scenario.toml", sc.text);
  std::string sets;
  for (const auto& o : sc.overrides) sets += o + "\n";
  write_file_atomically(dir / "overrides.txt", sets);
}

// A completed run's results: the analyses' values at the end, the inflow's rates and
// counts, each with its unit, in the scenario's order; the sources' grain sizes.
void add_results(RunSummary& summary, AnalysisMonitor& monitor, const Scenario& sc, const InflowFeed* inflow,
                 const World& world) {
  const std::vector<double>& values = monitor.evaluate(world);
  for (std::size_t k = 0; k < values.size(); ++k) summary.results[monitor.names()[k]] = values[k];
  for (const AnalysisSpec& a : sc.analyses)
    for (const std::string& unit : analysis_result_units(a)) summary.result_units.push_back(unit);
  summary.result_order = monitor.names();
  if (inflow)
    for (const auto& [name, value] : inflow->results(world)) {
      summary.results[name] = value;
      summary.result_order.push_back(name);
      summary.result_units.push_back(inflow_result_unit(name));
    }
  summary.sources = source_sizes(world);
}

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

// The time loop from world's state: from step 0 (from == nullptr; forces not yet computed)
// or from a checkpoint whose world state, forces included, is already in `world`.
RunSummary execute(const Scenario& sc, Simulation& sim, const std::string& out_dir, const std::string& run_id,
                   int threads, bool progress, const Checkpoint* from) {
  World& world = sim.world();
  const Model& model = sim.model();
  ForceField& forces = sim.forces();
  namespace fs = std::filesystem;
  const fs::path ckpt_dir = fs::path(out_dir) / "checkpoint";
  RunSummary summary;
  summary.particles = world.particles.size();
  // The inflow's grains enter at step boundaries (Simulation::step); the analyses give
  // series.csv columns, the results and the values the [[stop]] conditions watch.
  const InflowFeed* inflow = sim.inflow();
  AnalysisMonitor monitor(sc.analyses, sc.stops);
  std::string stop_reason;  // set by the first series row that meets a [[stop]] condition

  RunFiles files(sc, sim, out_dir, monitor.names(), from);
  // Entering grains bring energy: no energy-growth check with an inflow.
  EnergyWatch energy_watch(world, model, inflow ? 0.0 : sc.energy_growth_limit);
  if (from) energy_watch.restore(from->energy_watch);
  auto write_series = [&] {
    const Energies e = energies(world, model.gravity);
    const ContactTotals c = forces.totals(world);
    energy_watch.observe(world, c.elastic_energy);  // before the row: a failing state is not written
    const std::vector<double>& results = monitor.evaluate(world);  // before it too: a signal may cut it short
    files.series_row(sim, e, c, results);
    stop_reason = monitor.stop_reason(inflow && inflow->ended());
  };

  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  const Cadence cadence(sc);
  // A resumed run continues from checkpoints and ends with one even when its --set turned
  // the periodic ones off: a later resume from an older one would cut its outputs back.
  const bool checkpoints = cadence.checkpoint_steps > 0 || cadence.checkpoint_seconds > 0 || from;
  const Progress::Mode progress_mode_now = progress_mode(progress);
  const double log_interval = progress_mode_now == Progress::Mode::log ? progress_log_interval() : 0.0;
  const double wall_before = from ? from->wall_seconds : 0.0;  // earlier sessions
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  double last_checkpoint = 0;
  // Rows reach the files at least every second (tail -f, a kill before the first checkpoint);
  // flushed, not synced: a checkpoint syncs what it refers to.
  double last_flush = 0;
  auto flush_rows = [&] {
    files.flush();
    last_flush = elapsed();
  };
  std::int64_t checkpoint_step = from ? from->step : -1;  // step of the newest checkpoint
  // The stepping loop's totals over this session and the earlier ones the checkpoint counts.
  const Checkpoint::Record earlier = from ? from->record : Checkpoint::Record{};
  std::int64_t session_steps = 0;
  double session_seconds = 0;
  auto record = [&] {
    return Checkpoint::Record{true, world.source_ids, earlier.loop_seconds + session_seconds,
                              earlier.loop_steps + session_steps, earlier.loop_sessions + 1};
  };

  // Everything after a completed step; output files are flushed and synced first, so a
  // checkpoint never refers to rows that are not on disk.
  auto save_checkpoint = [&] {
    require_finite_energies(world, model.gravity, forces.totals(world).elastic_energy);  // only good states are kept
    flush_rows();
    Checkpoint c;
    store_simulation(sc, sim, c);
    c.run_id = run_id;
    c.energy_watch = energy_watch.state();
    c.record = record();
    c.wall_seconds = wall_before + elapsed();
    c.output = files.state();
    try {
      with_state_lent(sim, c, [&] {
        files.sync();
        write_checkpoint(ckpt_dir, c);
      });
      checkpoint_step = world.step;
    } catch (const std::exception& e) {
      // A run is worth more than its checkpoint: say so and carry on.
      std::fprintf(stderr, "\ntsubu: warning: no checkpoint at step %lld: %s\n", static_cast<long long>(world.step), e.what());
    }
    last_checkpoint = elapsed();
  };
  auto finish_summary = [&] {
    summary.steps = world.step;
    summary.particles = world.particles.size();
    summary.wall_seconds = wall_before + elapsed();
    summary.contact_evaluations = forces.evaluations();
    summary.list_builds = forces.rebuilds();
    summary.particle_force_evaluations = sim.particle_force_evaluations();
    if (const BlockHermite* b = sim.block()) summary.block_steps = b->stats();
    const Checkpoint::Record r = record();
    summary.loop_steps = r.loop_steps;
    summary.loop_seconds = r.loop_seconds;
    summary.loop_sessions = r.loop_sessions;
  };

  const std::string json = (fs::path(out_dir) / "run.json").string();
  // The end of a failure's message: checkpoints are written only after a completed step
  // whose outputs were written, never of a failing state.
  auto kept_checkpoint = [&]() -> std::string {
    if (checkpoint_step < 0) return "; no checkpoint was written before the failure";
    return "; the last good checkpoint (step " + std::to_string(checkpoint_step) + ") is kept in " + ckpt_dir.string();
  };
  if (checkpoints) prepare_checkpoint_folder(ckpt_dir, sc, !from);
  StopSignals stop_signals;
  try {
    if (!from) {
      sim.start();
      write_series();
      files.track_rows(world);
      if (cadence.vtk) files.frame(sim);
    }
    if (from && from->step % cadence.series == 0) {  // a run that a [[stop]] ended stays ended
      monitor.evaluate(world);
      stop_reason = monitor.stop_reason(inflow && inflow->ended());
    }
    const std::int64_t loop_first = world.step + 1;
    Progress report(progress_mode_now, log_interval, world.step, steps, elapsed());
    auto physics = [&] {
      const Energies e = energies(world, model.gravity);
      return ProgressPhysics{e.kinetic_translational + e.kinetic_rotational, forces.totals(world).contacts};
    };
    const auto loop_start = std::chrono::steady_clock::now();
    for (std::int64_t s = loop_first; s <= steps && stop_reason.empty(); ++s) {
      sim.step();
      session_steps = s - loop_first + 1;
      session_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
      if (s % cadence.series == 0 || s == steps) write_series();
      const bool last = s == steps || !stop_reason.empty();
      if (s % cadence.track == 0 || last) files.track_rows(world);
      if (cadence.vtk && (s % cadence.vtk == 0 || last)) files.frame(sim);
      if (g_stop_signal != 0) {
        const int sig = g_stop_signal;
        save_checkpoint();
        finish_summary();
        std::ostringstream msg;
        msg << "stopped by " << (sig == SIGINT ? "SIGINT" : "SIGTERM") << " after step " << world.step << " (t = " << world.time
            << " s); " << (checkpoint_step == world.step ? "a checkpoint of this step is" : "the newest checkpoint is")
            << " in " << ckpt_dir.string() << ": `tsubu resume " << out_dir << "` continues the run";
        write_run_json(json, run_id, sc, threads, summary, "interrupted", msg.str());
        throw Interrupted(msg.str());
      }
      if (!last && cadence.checkpoint_due(s, elapsed() - last_checkpoint))
        save_checkpoint();
      else if (elapsed() - last_flush >= 1.0)
        flush_rows();
      if (report.active() && report.due(elapsed()))
        report.report(s, world.time, elapsed(), physics, monitor.stop_progress(inflow && inflow->ended()));
    }
    report.finish();
    if (checkpoints && checkpoint_step != world.step) save_checkpoint();  // the final state
    files.close();
  } catch (const StopRequested&) {
    // SIGINT/SIGTERM during a long analysis: the step's outputs are not written, so this
    // step cannot be checkpointed; the newest checkpoint stays the last one.
    finish_summary();
    flush_rows();
    std::ostringstream msg;
    msg << "stopped by " << (g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM") << " during the analyses of step " << world.step
        << " (t = " << world.time << " s), whose outputs are not written; "
        << (checkpoint_step < 0 ? "no checkpoint was written before: run again"
                                : "the newest checkpoint (step " + std::to_string(checkpoint_step) + ") is in " +
                                      ckpt_dir.string() + ": `tsubu resume " + out_dir + "` continues the run");
    write_run_json(json, run_id, sc, threads, summary, "interrupted", msg.str());
    throw Interrupted(msg.str());
  } catch (const NumericalError& e) {
    // Nothing of the failing state goes into a checkpoint: the last good one stays.
    finish_summary();
    flush_rows();
    files.frame(sim);
    const std::string msg = e.what() + kept_checkpoint();
    write_run_json(json, run_id, sc, threads, summary, "failed", msg);
    throw NumericalError(msg);
  } catch (const WriteError& e) {
    finish_summary();
    const std::string msg = e.what() + kept_checkpoint();
    try {
      write_run_json(json, run_id, sc, threads, summary, "failed", msg);
    } catch (const WriteError&) {  // the disk that refused the output may refuse this too
    }
    throw WriteError(msg);
  }
  finish_summary();
  add_results(summary, monitor, sc, inflow, world);
  summary.stop_reason = stop_reason.empty() ? "duration" : stop_reason;
  write_run_json(json, run_id, sc, threads, summary, "ok", "");
  return summary;
}

// The keys a resume may set: none changes a step already taken or an output already written.
constexpr std::array<std::string_view, 6> kResumeKeys = {
    "simulation.duration",   "output.series_interval",         "output.vtk_interval",
    "output.track_interval", "output.checkpoint_every_steps", "output.checkpoint_every_seconds"};

// The run's scenario with the resume's --set values appended to its overrides. Output
// intervals that follow from the duration (unset in the scenario) keep the run's values
// unless set: pinned by overrides of their own, so that later resumes keep them too.
Scenario with_resume_overrides(const Scenario& run, const std::vector<std::string>& sets, std::int64_t step) {
  auto key_of = [](const std::string& set) { return set.substr(0, set.find('=')); };
  auto is_set = [&](std::string_view key) {
    return std::any_of(sets.begin(), sets.end(), [&](const std::string& set) { return key_of(set) == key; });
  };
  std::vector<std::string> overrides = run.overrides;
  overrides.insert(overrides.end(), sets.begin(), sets.end());
  // Loaded first: a key the scenario does not know, or a bad value, is reported as such.
  const Scenario changed = load_scenario_text(run.text, run.file, overrides, false);
  for (const std::string& set : sets)
    if (std::find(kResumeKeys.begin(), kResumeKeys.end(), key_of(set)) == kResumeKeys.end())
      throw InputError("--set " + set, 1, key_of(set),
                       "cannot change on resume: it could change the steps already taken or the outputs already "
                       "written; a resume may set simulation.duration, output.series_interval, output.vtk_interval, "
                       "output.track_interval, output.checkpoint_every_steps and output.checkpoint_every_seconds");
  std::vector<std::string> pins;
  auto pin = [&](const char* key, double was, double now) {
    char text[64];
    std::snprintf(text, sizeof text, "%s=%.17g", key, was);  // the same double when read back
    if (was != now && !is_set(key)) pins.push_back(text);
  };
  pin("output.series_interval", run.output.series_interval, changed.output.series_interval);
  pin("output.vtk_interval", run.output.vtk_interval, changed.output.vtk_interval);
  pin("output.track_interval", run.output.track_interval, changed.output.track_interval);
  if (std::llround(changed.duration / changed.dt) < step) {
    const auto it = std::find_if(sets.begin(), sets.end(), [&](const std::string& set) { return key_of(set) == "simulation.duration"; });
    char at[96];
    std::snprintf(at, sizeof at, "the run is already at step %lld (t = %.9g s)", static_cast<long long>(step),
                  static_cast<double>(step) * run.dt);
    throw InputError("--set " + *it, 1, "simulation.duration", std::string("cannot change on resume: ") + at);
  }
  if (pins.empty()) return changed;
  overrides.insert(overrides.end() - static_cast<std::ptrdiff_t>(sets.size()), pins.begin(), pins.end());
  return load_scenario_text(run.text, run.file, overrides, false);
}

// A resume continues the outputs from their length at the checkpoint and ends at the end of
// the run `sc` (as the checkpoint and the --sets give it): rows past that end, which a session
// that left no checkpoint of its end may have written, would be deleted and not written
// again. Refused, naming them and the --set that keeps them, before anything is touched.
void refuse_losing_rows(const Scenario& sc, const Checkpoint& c, const std::filesystem::path& used,
                        const std::string& out_dir) {
  namespace fs = std::filesystem;
  const double end = static_cast<double>(std::llround(sc.duration / sc.dt)) * sc.dt;
  std::string lost;
  double last = end;
  auto look = [&](const char* name, std::uint64_t bytes) {
    std::ifstream in(fs::path(out_dir) / name, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(bytes));
    std::size_t rows = 0;
    for (std::string line; std::getline(in, line) && !in.eof();) {  // complete rows only
      const double time = std::strtod(line.c_str(), nullptr);  // the first column
      if (time > end + 0.5 * sc.dt) ++rows, last = std::max(last, time);
    }
    if (rows > 0) lost += (lost.empty() ? "" : " and ") + std::to_string(rows) + " rows of " + name;
  };
  look("series.csv", c.output.series_bytes);
  if (!sc.output.track.empty()) look("track.csv", c.output.track_bytes);
  if (lost.empty()) return;
  throw UsageError(out_dir + " holds " + lost + " past t = " + format_number(end) + " s, up to t = " + format_number(last) +
                   " s: the end of the run as " + used.string() + " continues it (simulation.duration = " +
                   format_number(sc.duration) + " s); a session that left no checkpoint of its end wrote them, and a " +
                   "resume would delete them. Nothing was changed; resume with --set simulation.duration=" + format_number(last) +
                   " to write them again");
}

}  // namespace

RunSummary run_scenario(const Scenario& sc, const std::string& out_dir, int threads, bool progress, bool overwrite) {
  Simulation sim = new_simulation(sc);  // bad input is reported before the folder is touched
  for (const std::string& w : time_scales(sc, sim.world()).warnings) std::fprintf(stderr, "tsubu: WARNING: %s\n", w.c_str());
  const OutputDir owner = OutputDir::claim_new(out_dir, overwrite);
  return execute(sc, sim, out_dir, owner.run_id(), threads, progress, nullptr);
}

RunSummary resume_run(const std::string& out_dir, int threads, bool progress, const std::vector<std::string>& sets) {
  namespace fs = std::filesystem;
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
  const Scenario stored = scenario_of(c, used);
  const Scenario sc = sets.empty() ? stored : with_resume_overrides(stored, sets, c.step);
  refuse_losing_rows(sc, c, used, out_dir);
  Simulation sim = restore_simulation(sc, c, used);
  std::fprintf(stderr, "tsubu: resuming %s from %s (step %lld, t = %.9g s)\n", sc.name.c_str(), used.string().c_str(),
               static_cast<long long>(c.step), c.time);
  return execute(sc, sim, out_dir, owner.run_id(), threads, progress, &c);
}

}  // namespace tsubu
