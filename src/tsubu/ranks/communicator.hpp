// The processes of a run and the few collective operations a domain decomposition needs,
// on byte buffers: MPI's world communicator in a build with MPI (TSUBU_HAVE_MPI), one
// process otherwise. docs/parallel.md.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tsubu {

// Thrown on process 0 from a collective operation when another process has reported that it
// failed (Communicator::report_failure): the run ends with that process's message and exit
// code. what() is its message; `kind` is what the command line prints before it ("numerical
// failure: ", as for that error on one process).
class ProcessFailed : public std::runtime_error {
 public:
  ProcessFailed(int failed, int exit_code, std::string what_failed, const std::string& message)
      : std::runtime_error(message), process(failed), code(exit_code), kind(std::move(what_failed)) {}
  int process, code;
  std::string kind;
};

class Communicator {
 public:
  // The processes the run was started with (mpirun -np N), or one. Starts MPI.
  static Communicator& world();
  // Whether world() has started MPI (and it is not finished); false in a build without MPI.
  static bool started();
  // Ends every process of the job at once with exit code `code` (MPI_Abort), so that none
  // waits for ever for one that failed; without MPI started, this process (exit).
  [[noreturn]] static void end_job(int code);
  // On a process other than 0 that failed after the processes started working together:
  // sends its exit code, `kind` and `message` to process 0 and waits for it to end the job
  // (process 0 learns of it in its next collective operation, which throws ProcessFailed, so
  // that it records the failure in run.json and keeps its outputs). Should process 0 not end
  // the job within `patience_s`, this process prints its message and ends the job itself.
  [[noreturn]] void report_failure(int code, const std::string& kind, const std::string& message,
                                   double patience_s = 120.0) const;

  int rank() const { return rank_; }
  int size() const { return size_; }

  // Every collective operation below may throw ProcessFailed on process 0.

  // Sends to_each[r] to process r (to_each has size() entries, its own included) and returns
  // what each process sent to this one, by sender.
  std::vector<std::string> exchange(const std::vector<std::string>& to_each) const;
  // The same when each process knows how many bytes every other sends it (from_each, by
  // sender): one collective instead of two.
  std::vector<std::string> exchange(const std::vector<std::string>& to_each, const std::vector<std::size_t>& from_each) const;
  // Every process's bytes, by rank, on every process: views into `buffer`, which keeps its
  // largest size (no allocation once it is large enough), valid until it changes. Blocking:
  // for processes that fail alike (block steps' shares), as process 0 does not watch for
  // another's failure meanwhile (report_failure's patience then ends the job).
  std::vector<std::string_view> gather_all(const std::string& bytes, std::string& buffer) const;
  // Every process's bytes, by rank, on process 0; empty elsewhere.
  std::vector<std::string> gather(const std::string& bytes) const;
  // Whether any process passes true; the largest and the smallest value over the processes.
  bool any(bool mine) const;
  double max(double mine) const;
  double min(double mine) const;
  // Elementwise over the processes (every process passes as many): the sums (exact, in any
  // order) and the logical or (each flag 0 or 1).
  std::vector<std::int64_t> sum(std::vector<std::int64_t> mine) const;
  void any_each(std::vector<char>& flags) const;

 private:
  Communicator(int rank, int size) : rank_(rank), size_(size) {}
  int rank_, size_;
};

}  // namespace tsubu
