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
#include <iterator>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string_view>

#include <nlohmann/json.hpp>

#include "tsubu/analysis/energy_watch.hpp"
#include "tsubu/analysis/grain_sizes.hpp"
#include "tsubu/analysis/measures.hpp"
#include "tsubu/analysis/monitor.hpp"
#include "tsubu/analysis/profiles.hpp"
#include "tsubu/analysis/results.hpp"
#include "tsubu/scenario/result_names.hpp"
#include "tsubu/app/checkpoint.hpp"
#include "tsubu/app/progress.hpp"
#include "tsubu/app/simulation_state.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/core/format.hpp"
#include "tsubu/core/stop_signal.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu/io/output_dir.hpp"
#include "tsubu/io/frames.hpp"
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

// A result as run.json has always written it: whole numbers (counts) without a decimal
// point, other numbers to the last bit.
nlohmann::ordered_json result_value(double v) {
  if (std::isfinite(v) && v == std::trunc(v) && std::abs(v) < 0x1p53) return static_cast<std::int64_t>(v);
  return v;
}

// Written atomically: run.json is the old or the new one, never empty or cut short. A
// JSON library escapes the strings and writes non-finite numbers (the D50 of a source that
// gave no grain) as null.
void write_run_json(const std::string& path, const std::string& run_id, const Scenario& sc, int threads,
                    const RunSummary& s, const std::string& status, const std::string& message) {
  nlohmann::ordered_json j;
  j["engine"] = "tsubu";
  j["version"] = kVersion;
  j["run_id"] = run_id;
  j["scenario"] = sc.file;
  j["name"] = sc.name;
  std::ostringstream hash;
  hash << std::hex << sc.hash;
  j["scenario_hash"] = hash.str();
  j["status"] = status;
  j["message"] = message;
  if (!s.stop_reason.empty()) j["stop_reason"] = s.stop_reason;
  j["threads"] = threads;
  j["dt"] = sc.dt;
  j["steps"] = s.steps;
  j["particles"] = s.particles;
  j["integrator"] = integrator_name(sc.integrator);
  j["particle_force_evaluations"] = s.particle_force_evaluations;
  j["contact_evaluations"] = s.contact_evaluations;
  j["list_builds"] = s.list_builds;
  j["wall_time_s"] = s.wall_seconds;
  j["loop_time_s"] = s.loop_seconds;
  j["loop_sessions"] = s.loop_sessions;
  j["particle_steps_per_second"] = s.particle_steps_per_second();
  j["domain"] = {{"lower", {sc.domain.lower.x, sc.domain.lower.y, sc.domain.lower.z}},
                 {"upper", {sc.domain.upper.x, sc.domain.upper.y, sc.domain.upper.z}}};
  if (s.block_steps) {
    const BlockStepStats& b = *s.block_steps;
    const double total = static_cast<double>(s.particle_force_evaluations);
    std::vector<double> share;
    for (std::uint64_t n : b.evaluations) share.push_back(total > 0 ? static_cast<double>(n) / total : 0.0);
    j["block_steps"] = {{"levels", sc.block_steps.levels},
                        {"block_times", b.block_times},
                        {"wakes", b.wakes},
                        {"evaluation_share_per_level", share}};
  }
  // Before "results": a run resumed from a checkpoint of an older tsubu, which did not store
  // its sources' ids, leaves it out.
  if (!s.sources.empty()) {
    j["sources"] = nlohmann::ordered_json::array();
    for (const SourceSizes& g : s.sources)
      j["sources"].push_back({{"grains", g.grains}, {"d10", g.sizes.d10}, {"d50", g.sizes.d50}, {"d90", g.sizes.d90}});
  }
  j["results"] = nlohmann::ordered_json::object();
  for (const auto& [name, value] : s.results) j["results"][name] = result_value(value);
  write_file_atomically(path, j.dump(2) + "\n");
}

// The data rows of a CSV file: its lines after the header.
std::size_t data_rows(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const auto lines = std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
  return lines > 0 ? static_cast<std::size_t>(lines - 1) : 0;
}

}  // namespace

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

  // Moving walls add two columns each: the displacement of the plane along its normal and
  // the load the particles put on it.
  std::vector<std::size_t> moving;
  for (std::size_t k = 0; k < sc.walls.size(); ++k)
    if (!sc.walls[k].motion.empty()) moving.push_back(k);
  // Output files: fresh, or cut back to their size at the checkpoint (rows written after it
  // are written again, the same bits).
  auto reopen = [&](CheckedFile& f, const fs::path& path, std::uint64_t bytes) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec || size < bytes)
      throw std::runtime_error(path.string() + " is missing or shorter than at the checkpoint (" + std::to_string(bytes) +
                               " bytes): cannot continue it");
    fs::resize_file(path, bytes);
    f.open(path, CheckedFile::Mode::append);
  };
  const fs::path series_path = fs::path(out_dir) / "series.csv", track_path = fs::path(out_dir) / "track.csv";
  CheckedFile series;
  if (from) {
    reopen(series, series_path, from->output.series_bytes);
  } else {
    series.open(series_path);
    const std::vector<std::string> columns = series_columns(sc);
    for (std::size_t k = 0; k < columns.size(); ++k) series << (k > 0 ? "," : "") << columns[k];
    for (const std::string& name : monitor.names()) series << ',' << name;
    series << '\n';
  }
  series << std::setprecision(12);
  // type = "profiles": a row in each of its files with every series.csv row.
  std::optional<ProfileWriter> profiles;
  for (const AnalysisSpec& a : sc.analyses)
    if (a.kind == AnalysisSpec::Kind::profiles)
      profiles.emplace(a, fs::path(out_dir) / "profiles", from ? std::optional(data_rows(series_path)) : std::nullopt);
  FrameSeries frames(out_dir, sc.output.contacts, !world.walls.empty());
  if (from) frames.restore(from->output.pvd);
  // Index of particle `id` now (spatial sorting moves particles between indices).
  auto index_of = [&](std::int64_t id) {
    return static_cast<std::size_t>(std::find(world.particles.id.begin(), world.particles.id.end(), id) - world.particles.id.begin());
  };
  CheckedFile track;
  if (!sc.output.track.empty()) {
    if (from) {
      reopen(track, track_path, from->output.track_bytes);
    } else {
      track.open(track_path);
      track << "time,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,contacts\n";
    }
    track << std::setprecision(17);
  }
  auto write_track = [&] {
    const Particles& p = world.particles;
    for (std::int64_t id : sc.output.track) {
      const std::size_t i = index_of(id);
      if (i == p.size()) continue;  // an inflow grain not yet entered
      const Vec3 &x = p.position[i], &v = p.velocity[i], &w = p.omega[i], &f = p.force[i];
      track << world.time << ',' << p.id[i] << ',' << x.x << ',' << x.y << ',' << x.z << ',' << v.x << ',' << v.y << ','
            << v.z << ',' << w.x << ',' << w.y << ',' << w.z << ',' << f.x << ',' << f.y << ',' << f.z << ','
            << p.contact_count[i] << '\n';
    }
  };
  // Entering grains bring energy: no energy-growth check with an inflow.
  EnergyWatch energy_watch(world, model, inflow ? 0.0 : sc.energy_growth_limit);
  if (from) energy_watch.restore(from->energy_watch);
  auto write_series = [&] {
    const Energies e = energies(world, model.gravity);
    const ContactTotals c = forces.totals(world);
    energy_watch.observe(world, c.elastic_energy);  // before the row: a failing state is not written
    const std::vector<double>& results = monitor.evaluate(world);  // before it too: a signal may cut it short
    series << world.time << ',' << e.kinetic_translational << ',' << e.kinetic_rotational << ',' << e.potential_gravity
           << ',' << c.elastic_energy << ',' << c.contacts << ',' << c.max_overlap_ratio;
    for (std::size_t k : moving)
      series << ',' << dot(world.walls[k].point - sc.walls[k].point, world.walls[k].normal) << ','
             << forces.wall_load(world, k);
    if (sim.block())  // particles per level (step dt/2^k)
      for (std::size_t n : sim.block()->level_histogram()) series << ',' << n;
    if (inflow) series << ',' << world.particles.size() << ',' << inflow->mass_entered(world);
    for (double v : results) series << ',' << v;
    series << '\n';
    if (profiles) profiles->write(world);
    stop_reason = monitor.stop_reason(inflow && inflow->ended());
  };
  auto write_frame = [&] { frames.write(world, forces); };

  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  const std::int64_t series_every = every(sc.output.series_interval, sc.dt);
  const std::int64_t vtk_every = sc.output.vtk_interval > 0 ? every(sc.output.vtk_interval, sc.dt) : 0;
  const std::int64_t track_every = every(sc.output.track_interval, sc.dt);
  const std::int64_t ckpt_every = sc.output.checkpoint_every_steps;
  const double ckpt_seconds = sc.output.checkpoint_every_seconds;
  // A resumed run continues from checkpoints and ends with one even when its --set turned
  // the periodic ones off: a later resume from an older one would cut its outputs back.
  const bool checkpoints = ckpt_every > 0 || ckpt_seconds > 0 || from;
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
    series.flush();
    if (track.is_open()) track.flush();
    if (profiles) profiles->flush();
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
    c.output.frame = frames.count();
    c.output.pvd = frames.frames();
    c.output.series_bytes = fs::file_size(series_path);
    c.output.track_bytes = track.is_open() ? fs::file_size(track_path) : 0;
    try {
      with_state_lent(sim, c, [&] {
        sync_file(series_path);
        if (track.is_open()) sync_file(track_path);
        if (profiles)
          for (const fs::path& f : profiles->paths()) sync_file(f);
        for (const auto& f : frames.unsynced()) sync_file(f);
        frames.mark_synced();
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
  if (checkpoints) {
    fs::create_directories(ckpt_dir);
    // For people: the scenario as run (the checkpoints hold their own copy), with the
    // overrides of the run and of its resumes.
    if (!from) write_file_atomically(ckpt_dir / "scenario.toml", sc.text);
    std::string sets;
    for (const auto& o : sc.overrides) sets += o + "\n";
    write_file_atomically(ckpt_dir / "overrides.txt", sets);
  }
  StopSignals stop_signals;
  try {
    if (!from) {
      sim.start();
      write_series();
      write_track();
      if (vtk_every) write_frame();
    }
    if (from && from->step % series_every == 0) {  // a run that a [[stop]] ended stays ended
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
      if (s % series_every == 0 || s == steps) write_series();
      const bool last = s == steps || !stop_reason.empty();
      if (s % track_every == 0 || last) write_track();
      if (vtk_every && (s % vtk_every == 0 || last)) write_frame();
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
      if (!last && ((ckpt_every > 0 && s % ckpt_every == 0) || (ckpt_seconds > 0 && elapsed() - last_checkpoint >= ckpt_seconds)))
        save_checkpoint();
      else if (elapsed() - last_flush >= 1.0)
        flush_rows();
      if (report.active() && report.due(elapsed()))
        report.report(s, world.time, elapsed(), physics, monitor.stop_progress(inflow && inflow->ended()));
    }
    report.finish();
    if (checkpoints && checkpoint_step != world.step) save_checkpoint();  // the final state
    series.close();
    track.close();
    if (profiles) profiles->close();
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
    write_frame();
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
