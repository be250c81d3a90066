#include "tsubu/core/parallel.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace tsubu {

namespace {

// How long a waiting thread spins before it sleeps: on an idle machine the next loop, or the
// rest of the team at the end of one, mostly comes within it (with 50 us, 2 threads ran 7 %
// slower than OpenMP's team on the 20k bed); on a busy one the thread gives its core back
// after this long, a small part of a scheduler time slice (milliseconds).
constexpr auto kSpin = std::chrono::microseconds(200);

// True on the team's workers and on a thread while it runs its part of a team's work: a loop
// started there runs on that thread alone.
thread_local bool t_in_team = false;

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

// Returns once `value` differs from `old`: spins for up to kSpin, then sleeps on it (a futex).
template <class T>
void await_change(const std::atomic<T>& value, T old) {
  const auto until = std::chrono::steady_clock::now() + kSpin;
  for (unsigned k = 1; value.load(std::memory_order_acquire) == old; ++k) {
    if (k % 64 == 0 && std::chrono::steady_clock::now() > until) {
      value.wait(old, std::memory_order_acquire);
      continue;
    }
    relax();
  }
}

// threads - 1 workers that wait on a ticket each; the caller is thread 0.
class Team {
 public:
  void run(int threads, void (*call)(void*, int), void* context) {
    std::unique_lock<std::mutex> busy(mutex_, std::try_to_lock);
    if (!busy.owns_lock() || t_in_team || getpid() != pid_ || threads - 1 > kMaxWorkers) {  // nested, another
      // caller, a forked child (without the workers), or more threads than the team may have
      for (int t = 0; t < threads; ++t) call(context, t);
      return;
    }
    while (workers_ < threads - 1) start_worker();
    call_ = call;
    context_ = context;
    error_ = nullptr;
    pending_.store(threads - 1, std::memory_order_relaxed);
    for (int t = 1; t < threads; ++t) {  // the job is published by the release of each ticket
      Slot& s = slots_[static_cast<std::size_t>(t - 1)];
      s.ticket.fetch_add(1, std::memory_order_release);
      s.ticket.notify_one();
    }
    t_in_team = true;
    run_part(0);
    t_in_team = false;
    for (int left; (left = pending_.load(std::memory_order_acquire)) != 0;) await_change(pending_, left);
    if (error_) std::rethrow_exception(error_);
  }

 private:
  struct alignas(64) Slot {
    std::atomic<std::uint32_t> ticket{0};
  };
  static constexpr int kMaxWorkers = 1023;  // the command line's limit of 1024 threads

  std::mutex mutex_;  // held by the thread that runs a job
  pid_t pid_ = getpid();
  std::unique_ptr<Slot[]> slots_ = std::make_unique<Slot[]>(kMaxWorkers);
  int workers_ = 0;  // started, detached: the team lives as long as the process
  std::atomic<int> pending_{0};       // workers still working on the job
  void (*call_)(void*, int) = nullptr;
  void* context_ = nullptr;
  std::exception_ptr error_;
  std::mutex error_mutex_;

  void run_part(int t) {
    try {
      call_(context_, t);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }

  // Worker t waits for its ticket to change (0 until its first job), then runs part t of the job.
  void start_worker() {
    const int t = ++workers_;
    std::thread([this, t] {
      t_in_team = true;
      const std::atomic<std::uint32_t>& ticket = slots_[static_cast<std::size_t>(t - 1)].ticket;
      for (std::uint32_t seen = 0;; ++seen) {
        await_change(ticket, seen);
        run_part(t);
        if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_one();
      }
    }).detach();
  }
};

}  // namespace

void run_on_team(int threads, void (*call)(void*, int), void* context) {
  static Team* const team = new Team;  // never destroyed: its workers sleep until the process ends
  team->run(threads, call, context);
}

}  // namespace tsubu
