// `tsubu export`: a run's state at one of its checkpoints as a particle CSV (which a
// scenario reads back with source = "file") and a contact CSV (docs/cli.md).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>

namespace tsubu {

struct ExportedState {
  std::filesystem::path checkpoint, particles, contacts;
  std::int64_t step = 0;
  double time = 0;  // s
};

// Exports the checkpoint of out_dir/checkpoint at or just before `at` (s; the newest without
// it) into `to`. A time before every checkpoint throws UsageError; no valid checkpoint,
// std::runtime_error.
ExportedState export_checkpoint(const std::filesystem::path& out_dir, std::optional<double> at,
                                const std::filesystem::path& to);

}  // namespace tsubu
