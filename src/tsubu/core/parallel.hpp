// Parallel loops on a team of threads. Work is split into contiguous, equal static ranges so
// that per-thread results concatenated in thread order are the same for every thread count.
//
// The team is tsubu's own, not OpenMP's: a thread that waits for the next loop, or for the
// others at the end of one, spins only briefly and then sleeps. A waiting thread that keeps
// spinning (libgomp's default spins for milliseconds) stays runnable: when another process
// takes a core, the spinner holds the other one while the thread it waits for shares the
// busy core, and every loop waits a scheduler time slice (2 threads ran 11 times slower than
// 1 with one core busy). A sleeping thread frees its core, and the scheduler moves the
// thread that has work onto it.
#pragma once
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace tsubu {

// The threads a run uses: OpenMP's setting (OMP_NUM_THREADS, or omp_set_num_threads).
inline int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// Loops shorter than this run on one thread: waking the team costs more than the work.
inline constexpr long kParallelMin = 4096;

// Threads to use for n items of work.
inline int threads_for(std::size_t n) { return static_cast<long>(n) < kParallelMin ? 1 : thread_count(); }

// Runs call(context, t) for t = 0..threads-1 on the team, t = 0 on the calling thread, and
// returns when all have returned; the first exception a call throws is rethrown here. A call
// from inside a team's work, or while another thread uses the team, runs the calls one after
// the other on the calling thread (the same results).
void run_on_team(int threads, void (*call)(void*, int), void* context);

// Runs body(t) for t = 0..threads-1, one call per thread; with one thread the team is not
// woken at all.
template <class Body>
void for_each_thread(int threads, Body&& body) {
  if (threads == 1) {
    body(0);
    return;
  }
  using B = std::remove_reference_t<Body>;
  run_on_team(threads, [](void* b, int t) { (*static_cast<B*>(b))(t); }, &body);
}

inline std::pair<std::size_t, std::size_t> static_range(std::size_t n, int t, int threads) {
  const std::size_t T = static_cast<std::size_t>(threads), k = static_cast<std::size_t>(t);
  return {n * k / T, n * (k + 1) / T};
}

// body(i) for i = 0..n-1, in contiguous static ranges; serial below kParallelMin items.
template <class Body>
void parallel_for(std::size_t n, Body&& body) {
  const int threads = threads_for(n);
  for_each_thread(threads, [&](int t) {
    const auto [begin, end] = static_range(n, t, threads);
    for (std::size_t i = begin; i < end; ++i) body(i);
  });
}

// body(begin, end, local) over contiguous static ranges of 0..n, one per thread, each thread
// appending to its own cleared local[t]: concatenated in thread order, the lists are the same
// for every thread count.
template <class T, class Body>
void for_each_range(std::size_t n, std::vector<std::vector<T>>& local, Body&& body) {
  const int threads = threads_for(n);
  local.resize(static_cast<std::size_t>(threads));
  for_each_thread(threads, [&](int t) {
    auto& mine = local[static_cast<std::size_t>(t)];
    mine.clear();
    const auto [begin, end] = static_range(n, t, threads);
    body(begin, end, mine);
  });
}

}  // namespace tsubu
