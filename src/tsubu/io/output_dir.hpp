// A run owns its output folder (docs/reliability.md): the folder is locked for the run's
// lifetime, and a marker file names the run whose outputs it holds, so that a second run
// cannot mix its files into it and `resume` continues only a checkpoint of these outputs.
#pragma once
#include <filesystem>
#include <string>

namespace tsubu {

// Files of the folder itself: the marker holding the run id (also in run.json and every
// checkpoint), and the lock file (flock; it holds the pid, host and start of the holder).
inline constexpr const char* kRunMarker = ".tsubu-run";
inline constexpr const char* kLockFile = ".tsubu-lock";

class OutputDir {
 public:
  // For `tsubu run`: takes a new or empty folder, or (with `overwrite`) one that holds an
  // earlier run, which is cleared completely; then writes a new run id. A folder holding a
  // run without `overwrite`, a folder holding files of no run, and a folder locked by another
  // process are refused with UsageError.
  static OutputDir claim_new(const std::filesystem::path& dir, bool overwrite);
  // For `tsubu resume`: locks the folder and reads its run id (empty when the marker is
  // missing: not a run folder).
  static OutputDir claim_existing(const std::filesystem::path& dir);

  OutputDir(OutputDir&& other) noexcept;
  OutputDir& operator=(OutputDir&&) = delete;
  OutputDir(const OutputDir&) = delete;
  ~OutputDir();  // releases the lock

  const std::string& run_id() const { return run_id_; }

 private:
  explicit OutputDir(const std::filesystem::path& dir);
  std::filesystem::path dir_;
  int lock_fd_ = -1;
  std::string run_id_;
};

}  // namespace tsubu
