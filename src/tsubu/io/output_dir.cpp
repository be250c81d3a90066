#include "tsubu/io/output_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <random>
#include <vector>

#include "tsubu/core/error.hpp"
#include "tsubu/io/checked_file.hpp"

namespace tsubu {

namespace fs = std::filesystem;

namespace {

std::string first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// 64 random bits as 16 hex digits: unique enough to tell runs apart.
std::string new_run_id() {
  std::random_device rd;
  const std::uint64_t v = (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

// "pid 123 on host, since 2026-12-01T10:00:00Z": who holds the lock, for the one refused.
std::string holder_text() {
  char host[256] = "?";
  gethostname(host, sizeof host - 1);
  const std::time_t now = std::time(nullptr);
  char when[32];
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return "pid " + std::to_string(getpid()) + " on " + host + ", since " + when;
}

}  // namespace

OutputDir::OutputDir(const fs::path& dir) : dir_(dir) {
  if (dir.empty()) throw UsageError("the output folder is an empty path; give a folder name");
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UsageError(dir.string() + " exists and is not a folder; choose a folder for the outputs");
  fs::create_directories(dir);
  const fs::path lock = dir / kLockFile;
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw std::runtime_error("cannot create " + lock.string() + ": " + std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (err != EWOULDBLOCK) throw std::runtime_error("cannot lock " + lock.string() + ": " + std::strerror(err));
    const std::string holder = first_line(lock);
    throw UsageError(dir.string() + " is in use by another tsubu (" + (holder.empty() ? "holder unknown" : holder) +
                     "); wait for it to end or choose another output folder");
  }
  // The lock is released when the process ends, however it ends; the text is only for the
  // one refused and may be stale.
  const std::string text = holder_text() + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
    throw WriteError("cannot write " + lock.string() + ": " + std::strerror(errno));
}

OutputDir::OutputDir(OutputDir&& other) noexcept
    : dir_(std::move(other.dir_)), lock_fd_(other.lock_fd_), run_id_(std::move(other.run_id_)) {
  other.lock_fd_ = -1;
}

OutputDir::~OutputDir() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

OutputDir OutputDir::claim_new(const fs::path& dir, bool overwrite) {
  OutputDir out(dir);
  // A folder holds a run when it has the marker, or run.json (outputs of a tsubu before the
  // marker). Anything else in it is someone else's: never deleted, and never mixed with.
  bool run = false, other = false;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name == kLockFile) continue;
    if (name == kRunMarker || name == "run.json") run = true;
    else other = true;
  }
  if (run && !overwrite) {
    const std::string id = first_line(dir / kRunMarker);
    throw UsageError(dir.string() + " holds the outputs of another run" + (id.empty() ? "" : " (run id " + id + ")") +
                     "; add --overwrite to replace them (the folder is cleared first) or choose another output folder");
  }
  if (!run && other)
    throw UsageError(dir.string() + " is not empty and holds no tsubu run; choose an empty or new output folder "
                     "(--overwrite replaces only a tsubu run's folder)");
  if (run) {
    std::vector<fs::path> entries;  // listed first: removing while iterating is unspecified
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename() != kLockFile) entries.push_back(e.path());
    for (const auto& e : entries) fs::remove_all(e);
  }
  out.run_id_ = new_run_id();
  write_file_atomically(dir / kRunMarker, out.run_id_ + "\n");
  return out;
}

OutputDir OutputDir::claim_existing(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw UsageError(dir.string() + " is not a folder: nothing to resume");
  OutputDir out(dir);
  out.run_id_ = first_line(dir / kRunMarker);
  return out;
}

}  // namespace tsubu
