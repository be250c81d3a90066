#include "tsubu/app/run_checkpoints.hpp"

#include <cstdio>
#include <exception>

#include "tsubu/app/simulation_state.hpp"
#include "tsubu/io/checked_file.hpp"

namespace tsubu {

RunCheckpoints::RunCheckpoints(const Scenario& sc, const std::filesystem::path& out_dir, const Checkpoint* from)
    : dir_(out_dir / "checkpoint"),
      every_steps_(sc.output.checkpoint_every_steps),
      every_seconds_(sc.output.checkpoint_every_seconds),
      enabled_(every_steps_ > 0 || every_seconds_ > 0 || from),
      fresh_(!from),
      newest_step_(from ? from->step : -1) {
  if (!enabled_) return;
  std::filesystem::create_directories(dir_);
  if (fresh_) write_file_atomically(dir_ / "scenario.toml", sc.text);
  std::string sets;
  for (const auto& o : sc.overrides) sets += o + "\n";
  write_file_atomically(dir_ / "overrides.txt", sets);
}

bool RunCheckpoints::due(std::int64_t step, const RunClock& clock) const {
  return (every_steps_ > 0 && step % every_steps_ == 0) || (every_seconds_ > 0 && clock.elapsed() - last_ >= every_seconds_);
}

void RunCheckpoints::write(Simulation& sim, Checkpoint& c, const std::function<void()>& sync, const RunClock& clock) {
  try {
    with_state_lent(sim, c, [&] {
      sync();
      write_checkpoint(dir_, c);
    });
    newest_step_ = sim.world().step;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\ntsubu: warning: no checkpoint at step %lld: %s\n", static_cast<long long>(sim.world().step),
                 e.what());
  }
  last_ = clock.elapsed();
}

std::string RunCheckpoints::kept() const {
  if (newest_step_ < 0) return "; no checkpoint was written before the failure";
  return "; the last good checkpoint (step " + std::to_string(newest_step_) + ") is kept in " + dir_.string();
}

}  // namespace tsubu
