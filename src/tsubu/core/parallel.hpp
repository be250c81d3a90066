// OpenMP helpers. Work is split into contiguous, equal static ranges so that per-thread
// results concatenated in thread order are the same for every thread count.
#pragma once
#include <cstddef>
#include <utility>
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

inline std::pair<std::size_t, std::size_t> static_range(std::size_t n, int t, int threads) {
  const std::size_t T = static_cast<std::size_t>(threads), k = static_cast<std::size_t>(t);
  return {n * k / T, n * (k + 1) / T};
}

}  // namespace tsubu
