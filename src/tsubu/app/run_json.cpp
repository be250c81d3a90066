#include "tsubu/app/run_json.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "tsubu/integrate/integrators.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu/version.hpp"

namespace tsubu {

namespace {

// A result as run.json has always written it: whole numbers (counts) without a decimal
// point, other numbers to the last bit.
nlohmann::ordered_json result_value(double v) {
  if (std::isfinite(v) && v == std::trunc(v) && std::abs(v) < 0x1p53) return static_cast<std::int64_t>(v);
  return v;
}

}  // namespace

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
  if (!s.processes.empty()) {
    nlohmann::ordered_json each = nlohmann::ordered_json::array();
    for (const ProcessLoad& p : s.processes)
      each.push_back({{"owned", p.owned}, {"ghosts", p.ghosts}, {"listed_pairs", p.listed_pairs},
                      {"bytes_sent", p.bytes_sent}, {"arrangements", p.arrangements}});
    j["processes"] = {{"count", s.processes.size()},
                      {"cuts", {{"x", s.cuts[0]}, {"y", s.cuts[1]}, {"z", s.cuts[2]}}},
                      {"each", each}};
  }
  if (s.block_steps) {
    const BlockStepStats& b = *s.block_steps;
    const double total = static_cast<double>(s.particle_force_evaluations);
    std::vector<double> share;
    for (std::uint64_t n : b.evaluations) share.push_back(total > 0 ? static_cast<double>(n) / total : 0.0);
    nlohmann::ordered_json own, cluster;
    for (std::size_t r = 0; r < kStepRules; ++r) own[kStepRuleNames[r]] = b.set_by_own[r], cluster[kStepRuleNames[r]] = b.set_by_cluster[r];
    j["block_steps"] = {{"levels", sc.block_steps.levels},
                        {"block_times", b.block_times},
                        {"wakes", b.wakes},
                        {"evaluation_share_per_level", share},
                        {"steps_set_by_own_rule", own},
                        {"steps_set_by_cluster", cluster}};
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

}  // namespace tsubu
