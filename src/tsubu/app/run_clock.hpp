// A session's wall clock, and the stepping loops' totals over a run's sessions (run.json's
// loop_time_s and particle_steps_per_second; a checkpoint carries them to the next session).
#pragma once
#include <chrono>
#include <cstdint>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

class RunClock {
 public:
  // `from`: the checkpoint a resume continues from (its sessions are counted), or null.
  explicit RunClock(const Checkpoint* from)
      : wall_before_(from ? from->wall_seconds : 0.0), earlier_(from ? from->record : Checkpoint::Record{}) {}

  // Seconds since this session started.
  double elapsed() const { return seconds_since(start_); }
  // Seconds of all sessions.
  double wall_seconds() const { return wall_before_ + elapsed(); }
  // The stepping loop starts now, after step `step` (set-up, the first evaluation and the
  // final checkpoint are not counted).
  void loop_starts(std::int64_t step) {
    loop_start_ = std::chrono::steady_clock::now();
    loop_first_ = step + 1;
  }
  // The loop has completed step `step`.
  void stepped(std::int64_t step) {
    session_steps_ = step - loop_first_ + 1;
    session_seconds_ = seconds_since(loop_start_);
  }
  // What the run records across its sessions up to now, this one included.
  Checkpoint::Record record(const World& world) const {
    return Checkpoint::Record{true, world.source_ids, earlier_.loop_seconds + session_seconds_,
                              earlier_.loop_steps + session_steps_, earlier_.loop_sessions + 1};
  }

 private:
  using Clock = std::chrono::steady_clock;
  static double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
  double wall_before_;               // earlier sessions
  Checkpoint::Record earlier_;       // the loops of earlier sessions
  Clock::time_point start_ = Clock::now(), loop_start_ = start_;
  std::int64_t loop_first_ = 0, session_steps_ = 0;
  double session_seconds_ = 0;
};

}  // namespace tsubu
