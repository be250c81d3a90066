// run.json (docs/cli.md, output folder): a run's summary and measured results, written
// atomically at its end, after a failure and when it is interrupted.
#pragma once
#include <string>

#include "tsubu/app/runner.hpp"
#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

// Writes path (run.json) for the run `run_id` of `sc` on `threads` threads: status "ok",
// "failed" or "interrupted", with `message` saying why for the last two.
void write_run_json(const std::string& path, const std::string& run_id, const Scenario& sc, int threads,
                    const RunSummary& s, const std::string& status, const std::string& message);

}  // namespace tsubu
