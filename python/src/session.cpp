#include "session.hpp"

#include <stdexcept>

#include "tsubu/app/simulation_state.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/io/checked_file.hpp"

namespace tsubu::python {

Session::Session(Scenario scenario, Simulation sim) : scenario_(std::move(scenario)), sim_(std::move(sim)) {}

Session::Session(Scenario scenario) : scenario_(std::move(scenario)), sim_(new_simulation(scenario_)) { sim_.start(); }

Session Session::resume(const std::filesystem::path& file_or_dir) {
  namespace fs = std::filesystem;
  fs::path used = file_or_dir;
  Checkpoint c;
  if (fs::is_directory(file_or_dir)) {
    const fs::path run_folder = file_or_dir / "checkpoint";
    c = read_newest_checkpoint(fs::is_directory(run_folder) ? run_folder : file_or_dir, used);
  } else {
    c = read_checkpoint(file_or_dir);
  }
  Scenario sc = scenario_of(c, used);
  return Session(sc, restore_simulation(sc, c, used));
}

void Session::advance_to_step(std::int64_t target, const std::function<bool()>& go_on) {
  if (!failure_.empty())
    throw std::runtime_error("the run failed and cannot go on (" + failure_ + "); resume it from a checkpoint");
  if (target < world().step)
    throw std::invalid_argument("the run is at step " + std::to_string(world().step) + "; it cannot go back to step " +
                                std::to_string(target));
  try {
    while (world().step < target) {
      sim_.step();
      if (!go_on()) return;
    }
  } catch (const NumericalError& e) {
    failure_ = e.what();
    throw;
  }
}

bool Session::contacts_evaluated() const {
  return sim_.forces().evaluated(world());
}

void Session::checkpoint(const std::filesystem::path& file) {
  Checkpoint c;
  store_simulation(scenario_, sim_, c);
  with_state_lent(sim_, c, [&] { write_file_atomically(file, encode_checkpoint(c)); });
}

}  // namespace tsubu::python
