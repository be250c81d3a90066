// SIGINT or SIGTERM received by a run: app/runner.cpp's handler stores the signal here and the
// run stops after the step under way. A computation within a step that can take long (a
// porosity analysis's Monte Carlo points) calls poll_stop() now and then.
#pragma once
#include <chrono>
#include <csignal>
#include <stdexcept>

namespace tsubu {

inline volatile std::sig_atomic_t g_stop_signal = 0;          // the signal received, 0: none
inline std::chrono::steady_clock::time_point g_stop_seen{};  // when poll_stop() first saw it

// A signal cut a long computation short: the step's outputs cannot be written.
class StopRequested : public std::runtime_error {
 public:
  StopRequested() : std::runtime_error("stopped by a signal during a computation of the step") {}
};

inline void reset_stop_signal() {
  g_stop_signal = 0;
  g_stop_seen = {};
}

// Throws StopRequested once a signal has been seen for more than a second: computations that
// end sooner finish, so that their step ends and is checkpointed as usual.
inline void poll_stop() {
  if (g_stop_signal == 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (g_stop_seen == std::chrono::steady_clock::time_point{}) g_stop_seen = now;
  else if (now - g_stop_seen > std::chrono::seconds(1)) throw StopRequested();
}

}  // namespace tsubu
