#include "tsubu/app/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "tsubu/core/error.hpp"

namespace tsubu {

namespace {
constexpr double kTerminalInterval = 0.5;  // s between terminal updates
constexpr double kPhysicsAge = 2;          // s: oldest physics shown on the terminal
constexpr double kRateWindow = 10;         // s: time constant of the rate's moving average
}  // namespace

Progress::Progress(Mode mode, double log_interval, std::int64_t first_step, std::int64_t last_step, double now)
    : mode_(mode),
      interval_(mode == Mode::log ? log_interval : kTerminalInterval),
      next_(mode == Mode::off ? 1e300 : now + interval_),
      last_step_(last_step),
      prev_step_(first_step),
      prev_now_(now) {}

void Progress::report(std::int64_t step, double time, double now, const std::function<ProgressPhysics()>& physics,
                      const std::string& stops) {
  next_ = now + interval_;
  const double span = now - prev_now_;
  if (span > 0) {
    const double recent = static_cast<double>(step - prev_step_) / span;
    rate_ = rate_ > 0 ? rate_ + (1 - std::exp(-span / kRateWindow)) * (recent - rate_) : recent;
    prev_step_ = step;
    prev_now_ = now;
  }
  if (mode_ == Mode::log || now - physics_at_ >= kPhysicsAge) {
    physics_ = physics();
    physics_at_ = now;
  }
  const double done = 100.0 * static_cast<double>(step) / static_cast<double>(last_step_);
  const double eta = rate_ > 0 ? static_cast<double>(last_step_ - step) / rate_ : 0.0;
  const char* to = stops.empty() ? "" : " to the duration";
  if (mode_ == Mode::terminal)
    std::fprintf(stderr, "\r t = %.4g s  %5.1f%%  %.3g steps/s  ETA %.0f s%s  E_kin %.3g J  %zu contacts%s%s   ", time, done,
                 rate_, eta, to, physics_.kinetic, physics_.contacts, stops.empty() ? "" : "  stop: ", stops.c_str());
  else
    std::fprintf(stderr, "tsubu: progress: t = %.6g s, step %lld of %lld (%.1f%%), %.3g steps/s, ETA %.0f s%s, E_kin %.6g J, %zu contacts%s%s\n",
                 time, static_cast<long long>(step), static_cast<long long>(last_step_), done, rate_, eta, to,
                 physics_.kinetic, physics_.contacts, stops.empty() ? "" : "; [[stop]] ", stops.c_str());
}

void Progress::finish() const {
  if (mode_ == Mode::terminal) std::fprintf(stderr, "\n");
}

Progress::Mode progress_mode(bool enabled) {
  if (!enabled) return Progress::Mode::off;
  return isatty(STDERR_FILENO) ? Progress::Mode::terminal : Progress::Mode::log;
}

double progress_log_interval() {
  const char* text = std::getenv("TSUBU_LOG_INTERVAL");
  if (!text) return 30;
  char* end = nullptr;
  const double s = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(s > 0) || !std::isfinite(s))
    throw UsageError(std::string("TSUBU_LOG_INTERVAL=") + text + ": must be a number of seconds above 0 (between progress log lines)");
  return s;
}

}  // namespace tsubu
