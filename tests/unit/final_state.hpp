// A run's final state for comparisons between runs: its newest checkpoint, re-encoded.
#pragma once
#include <filesystem>
#include <string>

#include "tsubu/app/checkpoint.hpp"

namespace tsubu::testing {

// The newest checkpoint in OUT/checkpoint without what depends on when the sessions ran and
// how often they built their neighbour lists: the wall time, the loops' timings and sessions,
// the rebuild count; and without the run id, which is each run's own. The format itself
// leaves out the particles' numbering and the listed pairs that do not touch. `extended`:
// also without the overrides and the scenario hash (a run extended by a resume has the
// resume's --set values appended).
inline std::string final_state(const std::filesystem::path& out, bool extended = false) {
  const auto files = list_checkpoints(out / "checkpoint");
  if (files.empty()) return "no checkpoint";
  Checkpoint c = read_checkpoint(files.front());
  if (extended) c.overrides.clear(), c.scenario_hash = 0;
  c.wall_seconds = 0;
  c.record.loop_seconds = 0;
  c.record.loop_sessions = 0;
  c.counters.rebuilds = 0;
  c.run_id.clear();
  return encode_checkpoint(c);
}

}  // namespace tsubu::testing
