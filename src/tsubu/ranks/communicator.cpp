#include "tsubu/ranks/communicator.hpp"

#include <cstdlib>

#ifdef TSUBU_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <limits>
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

// A limit of MPI's (its counts and offsets are int) met on one process: the others are
// already inside the collective and would wait for ever, so the job ends here, saying why.
[[noreturn]] void abort_job(const std::string& why) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::fprintf(stderr, "tsubu: process %d: %s\n", rank, why.c_str());
  MPI_Abort(MPI_COMM_WORLD, 1);
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

std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each) const {
  std::vector<int> send_counts(static_cast<std::size_t>(size_)), receive_counts(send_counts.size());
  for (std::size_t r = 0; r < send_counts.size(); ++r) send_counts[r] = count_of(to_each[r].size());
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
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
  MPI_Alltoallv(sent.data(), send_counts.data(), send_at.data(), MPI_BYTE, received.data(), receive_counts.data(),
                receive_at.data(), MPI_BYTE, MPI_COMM_WORLD);
  std::vector<std::string> out(send_counts.size());
  for (std::size_t r = 0; r < out.size(); ++r)
    out[r] = received.substr(static_cast<std::size_t>(receive_at[r]), static_cast<std::size_t>(receive_counts[r]));
  return out;
}

std::vector<std::string> Communicator::gather(const std::string& bytes) const {
  const int mine = count_of(bytes.size());
  std::vector<int> counts(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> at = rank_ == 0 ? displacements(counts) : std::vector<int>{};
  std::string all(rank_ == 0 ? static_cast<std::size_t>(at.back() + counts.back()) : 0, '\0');
  MPI_Gatherv(bytes.data(), mine, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < counts.size(); ++r)
    out.push_back(all.substr(static_cast<std::size_t>(at[r]), static_cast<std::size_t>(counts[r])));
  return out;
}

bool Communicator::any(bool mine) const {
  int in = mine, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return out != 0;
}

double Communicator::max(double mine) const {
  double out = 0;
  MPI_Allreduce(&mine, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

double Communicator::min(double mine) const {
  double out = 0;
  MPI_Allreduce(&mine, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

std::vector<std::int64_t> Communicator::sum(std::vector<std::int64_t> mine) const {
  MPI_Allreduce(MPI_IN_PLACE, mine.data(), count_of(mine.size()), MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return mine;
}

void Communicator::any_each(std::vector<char>& flags) const {
  MPI_Allreduce(MPI_IN_PLACE, flags.data(), count_of(flags.size()), MPI_UNSIGNED_CHAR, MPI_BOR, MPI_COMM_WORLD);
}

#else  // one process

Communicator& Communicator::world() {
  static Communicator c(0, 1);
  return c;
}

bool Communicator::started() { return false; }
void Communicator::end_job(int code) { std::exit(code); }
std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each) const { return to_each; }
std::vector<std::string> Communicator::exchange(const std::vector<std::string>& to_each,
                                                const std::vector<std::size_t>&) const {
  return to_each;
}
std::vector<std::string> Communicator::gather(const std::string& bytes) const { return {bytes}; }
bool Communicator::any(bool mine) const { return mine; }
double Communicator::max(double mine) const { return mine; }
double Communicator::min(double mine) const { return mine; }
std::vector<std::int64_t> Communicator::sum(std::vector<std::int64_t> mine) const { return mine; }
void Communicator::any_each(std::vector<char>&) const {}

#endif

}  // namespace tsubu
