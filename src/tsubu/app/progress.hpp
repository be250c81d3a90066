// The progress report on stderr (docs/cli.md): on a terminal, one line rewritten every
// 0.5 s; otherwise a plain log line every `log_interval` seconds of wall time, so that batch
// logs show the run going. Rate and ETA come from the recent rate (an exponential moving
// average over about the last 10 s), not the average since the start; the physics (kinetic
// energy, contacts) from a pass over the state at most every 2 s.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace tsubu {

struct ProgressPhysics {
  double kinetic = 0;        // J, translational + rotational
  std::size_t contacts = 0;  // pairs + walls
};

class Progress {
 public:
  enum class Mode { off, terminal, log };
  // From `first_step` (done) at `now` wall seconds to `last_step`.
  Progress(Mode mode, double log_interval, std::int64_t first_step, std::int64_t last_step, double now);
  bool active() const { return mode_ != Mode::off; }
  bool due(double now) const { return now >= next_; }
  // After `step` (simulated time `time`); `physics` is called when the last values are
  // older than 2 s (and for every log line). `stops`: where the [[stop]] conditions stand
  // (AnalysisMonitor::stop_progress), shown after the rest; the percentage and ETA are then
  // said to count to the duration, which a condition may cut short.
  void report(std::int64_t step, double time, double now, const std::function<ProgressPhysics()>& physics,
              const std::string& stops = "");
  void finish() const;  // ends the terminal line

 private:
  Mode mode_;
  double interval_, next_, physics_at_ = -1e300;
  std::int64_t last_step_, prev_step_;
  double prev_now_, rate_ = 0;  // steps/s, moving average
  ProgressPhysics physics_;
};

// The mode for stderr (off unless `enabled`), and the seconds between log lines:
// TSUBU_LOG_INTERVAL (default 30); a value that is not a number above 0 throws UsageError.
Progress::Mode progress_mode(bool enabled);
double progress_log_interval();

}  // namespace tsubu
