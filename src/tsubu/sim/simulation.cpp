#include "tsubu/sim/simulation.hpp"

namespace tsubu {

Simulation::Simulation(World world, Integrator integrator, const BlockStepRules& block_steps)
    : world_(std::move(world)), integrator_(integrator) {
  if (integrator_ == Integrator::block_hermite) block_ = std::make_unique<BlockHermite>(block_steps);
}

void Simulation::start() {
  if (block_) block_->start(world_, forces_);
  else forces_.compute(world_);
}

void Simulation::step() {
  if (block_) block_->advance(world_, forces_);
  else advance(integrator_, world_, forces_);
}

void Simulation::advance_to(std::int64_t step) {
  while (world_.step < step) this->step();
}

std::uint64_t Simulation::particle_force_evaluations() const {
  if (block_) return block_->particle_evaluations();
  return static_cast<std::uint64_t>(world_.particles.size()) * static_cast<std::uint64_t>(world_.step + 1);
}

}  // namespace tsubu
