// A run's state and its time loop as a library: the world (state), the model (physics), the
// force field that evaluates one under the other, and the integrator that advances them.
// The command line drives it (app/runner.cpp), adding files, progress and signals around
// it; other drivers (Python, MPI) drive the same object.
#pragma once
#include <cstdint>
#include <exception>
#include <memory>
#include <optional>
#include <utility>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/integrate/block_hermite.hpp"
#include "tsubu/integrate/integrators.hpp"
#include "tsubu/sim/inflow_feed.hpp"
#include "tsubu/sim/outflow.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

class Simulation {
 public:
  // `world` at its start (step 0, forces not yet evaluated) or restored from a checkpoint.
  Simulation(World world, Model model, Integrator integrator, const BlockStepRules& block_steps);

  // The scenario's inflow, fed from now on: after start() and after every step the grains
  // due by then enter and join the run (particles_added).
  void feed(InflowFeed inflow);
  const InflowFeed* inflow() const { return inflow_ ? &*inflow_ : nullptr; }
  // The mass of the inflow's grains that have entered the box (kg), those gone through an
  // open face since included.
  double inflow_mass_entered() const;

  // The box's open faces (domain.open): grains beyond one are removed before each force
  // evaluation of fixed steps, or at the end of each block step, and recorded here (in a
  // split run, every process's). Null for a box without open faces.
  Outflow* outflow() { return outflow_ ? &*outflow_ : nullptr; }
  const Outflow* outflow() const { return outflow_ ? &*outflow_ : nullptr; }

  // A fresh run: the first force evaluation (and, for block steps, the first steps); then
  // the inflow's first grains enter.
  void start();
  // One step of dt: one fixed step, or for block steps every block time up to the next
  // multiple of dt (where every particle's time is the same); then the inflow's grains due
  // enter. The particles are renumbered along a space-filling curve (sort_spatially) at
  // every search.sort_every-th step: before the evaluation at that step (fixed steps) or
  // before the block times from it (block steps). With fixed steps a failed force check
  // (an overlap beyond simulation.overlap_limit, a force that is not finite: NumericalError)
  // ends the step first, its last kick included, and is thrown at its end, before the
  // inflow's grains enter: a run split among processes gathers that state from every process
  // for the failing state's frame (step_to_its_end, ObservedRun). A particle the drift takes
  // out of the box (ParticleLost) ends the step after its drift, the walls moved and the
  // clock at the step's end, before the evaluation.
  void step() {
    if (std::exception_ptr failure = step_to_its_end()) std::rethrow_exception(failure);
  }
  // step(), but the failed force check returned instead of thrown (null: none); the inflow's
  // grains then do not enter. In a run split among processes a lost particle is returned too,
  // on its process, and StepAbandoned on the others, each having ended the step where the
  // failing process's was (after the drift). With block steps, every failure (NumericalError)
  // at the block time where it happened.
  std::exception_ptr step_to_its_end();
  // Steps until world().step == step.
  void advance_to(std::int64_t step);
  // Particles appended to world().particles between steps (from index `first` on, e.g. by an
  // inflow) join the run: they must not touch anything; they start with the forces of
  // gravity and the fluid (and, for block steps, with their own first steps).
  void particles_added(std::size_t first);

  World& world() { return world_; }
  const World& world() const { return world_; }
  const Model& model() const { return *model_; }
  ForceField& forces() { return forces_; }
  const ForceField& forces() const { return forces_; }
  Integrator integrator() const { return integrator_; }
  // The block-step integrator, or null for fixed steps.
  BlockHermite* block() { return block_.get(); }
  const BlockHermite* block() const { return block_.get(); }

  // The smallest and the largest radius of the particles, and of the grains the inflow can
  // release ({0, 0} for none).
  std::pair<double, double> radius_range() const;

  // Single-particle force evaluations so far: the particles of each evaluation summed over
  // them for fixed steps (each grain of an inflow from its entry on), the sum of the active
  // sets for block steps.
  std::uint64_t particle_force_evaluations() const;

 private:
  std::unique_ptr<const Model> model_;  // where the force field finds it, however the Simulation moves
  World world_;
  ForceField forces_{*model_};
  Integrator integrator_;
  std::unique_ptr<BlockHermite> block_;
  std::optional<InflowFeed> inflow_;
  std::optional<Outflow> outflow_;

  void admit_inflow();
  // The fixed steps' force evaluation at the state the step has reached (the integrators'
  // callable): the grains gone through an open face removed, the sort schedule, then the
  // force field.
  void evaluate(double fluid_lead);
  // Block steps: the grains gone through an open face removed at the end of each step.
  void remove_departed_at_block_end();
  // A run split among processes: each finds its own particles gone through an open face,
  // every process records all of them (in the order of their ids) and drops them.
  // `lost`: this process's drift lost a particle (announce_loss).
  void remove_departed_among_processes(Neighbourhood& split, bool lost);
  // A split run's process whose drift lost a particle (ParticleLost) takes part in the
  // step's first exchange, which ends the step on every process (StepAbandoned).
  void announce_loss(Neighbourhood& split);
  bool sort_due() const;
  // One renumbering for every per-particle store: the world's particles and contacts, the
  // force field's lists, the block-step state.
  void renumber();
};

}  // namespace tsubu
