#include "tsubu/ranks/communicator.hpp"

#include <cstdio>
#include <cstdlib>

#ifdef TSUBU_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <thread>
#endif

namespace tsubu {

#ifdef TSUBU_HAVE_MPI

namespace {

// MPI is started at the first use and finished at the process's exit.
void start_mpi() {
  int started = 0;
  MPI_Initialized(&started);
  if (started) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);  // OpenMP threads never call MPI
  std::atexit([] {
    int finished = 0;
    MPI_Finalized(&finished);
    if (!finished) MPI_Finalize();
  });
}

// Ends the job from this process, saying why, with exit code `code`: a limit of MPI's (its
// counts and offsets are int) met on one process, whose others are already inside the
// collective and would wait for ever; a failure process 0 did not end the job for.
[[noreturn]] void abort_job(const std::string& why, int code = 1) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::fprintf(stderr, "tsubu: process %d: %s\n", rank, why.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // MPI_Abort does not return
}

// Where each process's bytes begin in one buffer.
std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> at(counts.size(), 0);
  long long total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    at[r] = static_cast<int>(std::min<long long>(total, std::numeric_limits<int>::max()));
    total += counts[r];
  }
  if (total > std::numeric_limits<int>::max())
    abort_job("the messages of all processes to this one exceed 2 GiB in one exchange (MPI counts bytes in int)");
  return at;
}

int count_of(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    abort_job("a message to another process exceeds 2 GiB (MPI counts bytes in int)");
  return static_cast<int>(bytes);
}

// A process's report of its failure to process 0 (report_failure): point to point, which
// never matches a collective operation.
constexpr int kFailureTag = 1;

// The report of the process `status` names, received.
ProcessFailed received_failure(const MPI_Status& status) {
  int bytes = 0;
  MPI_Get_count(&status, MPI_BYTE, &bytes);
  std::string report(static_cast<std::size_t>(bytes), '\0');
  MPI_Recv(report.data(), bytes, MPI_BYTE, status.MPI_SOURCE, kFailureTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  // "code\nkind\nmessage" (report_failure)
  const std::size_t a = report.find('\n'), b = report.find('\n', a + 1);
  return ProcessFailed(status.MPI_SOURCE, std::atoi(report.substr(0, a).c_str()), report.substr(a + 1, b - a - 1),
                       report.substr(b + 1));
}

// Waits for a collective operation of this process to complete. Process 0 watches meanwhile
// for a failure reported by another process, which would never join it: it throws
// ProcessFailed instead of waiting for ever (the job then ends: the request is abandoned).
void complete(MPI_Request& request, int rank) {
  if (rank != 0) {
    MPI_Wait(&request, MPI_STATUS_IGNORE);
    return;
  }
  for (int tries = 1;; ++tries) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    if (tries % 64 != 0) continue;
    int reported = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kFailureTag, MPI_COMM_WORLD, &reported, &status);
    if (reported) throw received_failure(status);
    std::this_thread::yield();  // processes may outnumber cores
  }
}

}  // namespace

Communicator& Communicator::world() {
  static Communicator c = [] {
    start_mpi();
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    return Communicator(rank, size);
  }();
  return c;
}

bool Communicator::started() {
  int started = 0, finished = 0;
  MPI_Initialized(&started);
  MPI_Finalized(&finished);
  return started && !finished;
}

void Communicator::end_job(int code) {
  if (started()) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

void Communicator::report_failure(int code, const std::string& kind, const std::string& message, double patience_s) const {
  if (rank_ != 0) {
    std::string report = std::to_string(code) + '\n' + kind + '\n' + message;
    MPI_Request sent;
    MPI_Isend(report.data(), count_of(report.size()), MPI_BYTE, 0, kFailureTag, MPI_COMM_WORLD, &sent);
    const auto given_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(patience_s);
    while (std::chrono::steady_clock::now() < given_up) {
      int done = 0;
      MPI_Test(&sent, &done, MPI_STATUS_IGNORE);  // progress; process 0 ends the job
      std::this_thread::sleep_for(std::chrono::milliseconds(done ? 50 : 1));
    }
  }
  abort_job(kind + message, code);
}

std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each) const {
  std::vector<int> send_counts(static_cast<std::size_t>(size_)), receive_counts(send_counts.size());
  for (std::size_t r = 0; r < send_counts.size(); ++r) send_counts[r] = count_of(to_each[r].size());
  MPI_Request request;
  MPI_Ialltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, MPI_COMM_WORLD, &request);
  complete(request, rank_);
  std::vector<std::size_t> from_each(receive_counts.begin(), receive_counts.end());
  return exchange(to_each, from_each);
}

std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each,
                                                const std::vector<std::size_t>& from_each) const {
  std::vector<int> send_counts(static_cast<std::size_t>(size_)), receive_counts(send_counts.size());
  for (std::size_t r = 0; r < send_counts.size(); ++r)
    send_counts[r] = count_of(to_each[r].size()), receive_counts[r] = count_of(from_each[r]);
  std::string sent;
  for (const std::string& s : to_each) sent += s;
  const std::vector<int> send_at = displacements(send_counts), receive_at = displacements(receive_counts);
  std::string received(static_cast<std::size_t>(receive_at.back() + receive_counts.back()), '\0');
  MPI_Request request;
  MPI_Ialltoallv(sent.data(), send_counts.data(), send_at.data(), MPI_BYTE, received.data(), receive_counts.data(),
                 receive_at.data(), MPI_BYTE, MPI_COMM_WORLD, &request);
  complete(request, rank_);
  std::vector<std::string> out(send_counts.size());
  for (std::size_t r = 0; r < out.size(); ++r)
    out[r] = received.substr(static_cast<std::size_t>(receive_at[r]), static_cast<std::size_t>(receive_counts[r]));
  return out;
}

std::vector<std::string_view> Communicator::gather_all(const std::string& bytes, std::string& buffer) const {
  const int mine = count_of(bytes.size());
  std::vector<int> counts(static_cast<std::size_t>(size_));
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const std::vector<int> at = displacements(counts);
  const auto total = static_cast<std::size_t>(at.back() + counts.back());
  if (buffer.size() < total) buffer.resize(total);
  MPI_Allgatherv(bytes.data(), mine, MPI_BYTE, buffer.data(), counts.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD);
  std::vector<std::string_view> out;
  for (std::size_t r = 0; r < counts.size(); ++r)
    out.emplace_back(buffer.data() + at[r], static_cast<std::size_t>(counts[r]));
  return out;
}

std::vector<std::string> Communicator::gather(const std::string& bytes) const {
  const int mine = count_of(bytes.size());
  std::vector<int> counts(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  MPI_Request request;
  MPI_Igather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
  complete(request, rank_);
  std::vector<int> at = rank_ == 0 ? displacements(counts) : std::vector<int>{};
  std::string all(rank_ == 0 ? static_cast<std::size_t>(at.back() + counts.back()) : 0, '\0');
  MPI_Igatherv(bytes.data(), mine, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, 0, MPI_COMM_WORLD, &request);
  complete(request, rank_);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < counts.size(); ++r)
    out.push_back(all.substr(static_cast<std::size_t>(at[r]), static_cast<std::size_t>(counts[r])));
  return out;
}

namespace {

// Combines `count` values of `type` of every process by `op`, in place, on every process.
void all_reduce(void* values, int count, MPI_Datatype type, MPI_Op op, int rank) {
  MPI_Request request;
  MPI_Iallreduce(MPI_IN_PLACE, values, count, type, op, MPI_COMM_WORLD, &request);
  complete(request, rank);
}

}  // namespace

bool Communicator::any(bool mine) const {
  int value = mine;
  all_reduce(&value, 1, MPI_INT, MPI_LOR, rank_);
  return value != 0;
}

double Communicator::max(double mine) const {
  all_reduce(&mine, 1, MPI_DOUBLE, MPI_MAX, rank_);
  return mine;
}

double Communicator::min(double mine) const {
  all_reduce(&mine, 1, MPI_DOUBLE, MPI_MIN, rank_);
  return mine;
}

std::vector<std::int64_t> Communicator::sum(std::vector<std::int64_t> mine) const {
  all_reduce(mine.data(), count_of(mine.size()), MPI_INT64_T, MPI_SUM, rank_);
  return mine;
}

void Communicator::any_each(std::vector<char>& flags) const {
  all_reduce(flags.data(), count_of(flags.size()), MPI_UNSIGNED_CHAR, MPI_BOR, rank_);
}

#else  // one process

Communicator& Communicator::world() {
  static Communicator c(0, 1);
  return c;
}

bool Communicator::started() { return false; }
void Communicator::end_job(int code) { std::exit(code); }
void Communicator::report_failure(int code, const std::string& kind, const std::string& message, double) const {
  std::fprintf(stderr, "tsubu: process %d: %s%s\n", rank_, kind.c_str(), message.c_str());
  end_job(code);
}
std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each) const { return to_each; }
std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each,
                                                const std::vector<std::size_t>&) const {
  return to_each;
}
std::vector<std::string_view> Communicator::gather_all(const std::string& bytes, std::string& buffer) const {
  buffer = bytes;
  return {buffer};
}
std::vector<std::string> Communicator::gather(const std::string& bytes) const { return {bytes}; }
bool Communicator::any(bool mine) const { return mine; }
double Communicator::max(double mine) const { return mine; }
double Communicator::min(double mine) const { return mine; }
std::vector<std::int64_t> Communicator::sum(std::vector<std::int64_t> mine) const { return mine; }
void Communicator::any_each(std::vector<char>&) const {}

#endif

}  // namespace tsubu
