// The run behind tsubu.Simulation: a scenario, its Simulation and its inflow, started and
// stepped as the command line does it (app/runner.cpp), so that a run driven from Python
// gives the same bits. Free of Python: the binding (module.cpp) adds arrays, the GIL and
// Ctrl-C around it.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/inflow_feed.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu::python {

class Session {
 public:
  // A fresh run at step 0, its first force evaluation done (and the inflow's first grains
  // admitted), as `tsubu run` starts.
  explicit Session(Scenario scenario);
  // Continues a checkpoint: a file, or the newest valid one of a folder (a run's output
  // folder, whose checkpoint/ is used, or a folder of step_*.tsbk files).
  static Session resume(const std::filesystem::path& file_or_dir);

  // Steps until world().step == target (an earlier target throws std::invalid_argument).
  // After every step `go_on()` is asked whether to continue; false stops there, between two
  // steps. A NumericalError leaves the failing state for inspection and the session
  // refuses to step again.
  void advance_to_step(std::int64_t target, const std::function<bool()>& go_on);

  // The current state, particles and contact lists lent to it, in `file` (written atomically).
  // tsubu.Simulation.resume reads it; `tsubu resume` reads only the checkpoints of its runs.
  void checkpoint(const std::filesystem::path& file);

  const Scenario& scenario() const { return scenario_; }
  Simulation& simulation() { return sim_; }
  const Simulation& simulation() const { return sim_; }
  World& world() { return sim_.world(); }
  const World& world() const { return sim_.world(); }
  const Model& model() const { return sim_.model(); }
  // The particle count can change between steps (grains enter, or leave through an open
  // face): arrays are copied, not viewed.
  bool count_changes() const { return sim_.inflow() != nullptr || sim_.outflow() != nullptr; }
  // Whether the force field's per-contact results belong to the current contact lists: not
  // after a resume until the next step (a checkpoint stores forces, not contact results).
  bool contacts_evaluated() const;
  // Whether the arrays positions, velocities and spins may be written (fixed-step
  // integrators only: docs/python.md, writing the state).
  bool state_writable() const { return !sim_.block(); }

 private:
  Session(Scenario scenario, Simulation sim);
  Scenario scenario_;
  Simulation sim_;
  std::string failure_;  // the NumericalError that stopped the run, if one did
};

}  // namespace tsubu::python
