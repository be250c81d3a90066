// OpenMP helpers. Work is split into contiguous, equal static ranges so that per-thread
// results concatenated in thread order are the same for every thread count.
#pragma once
#include <cstddef>
#include <utility>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace tsubu {

inline int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// Loops shorter than this run on one thread: a parallel region costs more than the work.
inline constexpr long kParallelMin = 4096;

// Threads to use for n items of work.
inline int threads_for(std::size_t n) { return static_cast<long>(n) < kParallelMin ? 1 : thread_count(); }

inline int thread_index() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

// Runs body(t) for t = 0..threads-1, one call per thread; with one thread no parallel
// region is opened at all (even an empty team wakes the OpenMP workers).
template <class Body>
void for_each_thread(int threads, Body&& body) {
  if (threads == 1) {
    body(0);
    return;
  }
#pragma omp parallel num_threads(threads)
  body(thread_index());
}

// body(i) for i = 0..n-1, statically scheduled; serial below kParallelMin items.
template <class Body>
void parallel_for(std::size_t n, Body&& body) {
  const long count = static_cast<long>(n);
  if (threads_for(n) == 1) {
    for (long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
    return;
  }
#pragma omp parallel for schedule(static)
  for (long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
}

inline std::pair<std::size_t, std::size_t> static_range(std::size_t n, int t, int threads) {
  const std::size_t T = static_cast<std::size_t>(threads), k = static_cast<std::size_t>(t);
  return {n * k / T, n * (k + 1) / T};
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
