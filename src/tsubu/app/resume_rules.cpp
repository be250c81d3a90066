#include "tsubu/app/resume_rules.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string_view>

#include "tsubu/core/error.hpp"
#include "tsubu/core/format.hpp"

namespace tsubu {

namespace {

// The keys a resume may set: none changes a step already taken or an output already written
// (nor any bit of one: the grid of subdomains of a split run changes none).
constexpr std::array<std::string_view, 7> kResumeKeys = {
    "simulation.duration",           "output.series_interval",          "output.vtk_interval", "output.track_interval",
    "output.checkpoint_every_steps", "output.checkpoint_every_seconds", "parallel.counts"};

}  // namespace

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
                       "output.track_interval, output.checkpoint_every_steps, output.checkpoint_every_seconds and "
                       "parallel.counts");
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
  if (sc.domain.any_open()) look("outflow.csv", c.output.outflow_bytes);
  if (lost.empty()) return;
  throw UsageError(out_dir + " holds " + lost + " past t = " + format_number(end) + " s, up to t = " + format_number(last) +
                   " s: the end of the run as " + used.string() + " continues it (simulation.duration = " +
                   format_number(sc.duration) + " s); a session that left no checkpoint of its end wrote them, and a " +
                   "resume would delete them. Nothing was changed; resume with --set simulation.duration=" + format_number(last) +
                   " to write them again");
}

}  // namespace tsubu
