// Fixed-step integrators with rotation. Both expect world.particles.force/torque to hold
// the forces at the current state when called (one evaluation before the first step), and
// receive the force evaluation as a callable: evaluate(fluid_lead) sets every particle's
// force and torque at the positions and time the step has reached (Simulation::evaluate:
// the sort schedule, then ForceField::compute; fluid_lead as ForceField::compute takes it).
#pragma once
#include <array>

#include "tsubu/world/world.hpp"

namespace tsubu {

// block_hermite: BlockHermite (block_hermite.hpp), not a fixed-step scheme.
enum class Integrator { symplectic_euler, velocity_verlet, block_hermite };

// The scenario's name of an integrator (simulation.integrator).
constexpr const char* integrator_name(Integrator i) {
  switch (i) {
    case Integrator::symplectic_euler: return "symplectic_euler";
    case Integrator::velocity_verlet: return "velocity_verlet";
    case Integrator::block_hermite: return "block_hermite";
  }
  return "";
}
// Every integrator, the default (velocity Verlet) first.
inline constexpr std::array kIntegrators = {Integrator::velocity_verlet, Integrator::symplectic_euler, Integrator::block_hermite};

// The phases of a fixed step. Forces are divided by the translational mass (mass plus the
// fluid's added mass).
// v <- v + F/m h_kick, x <- x + v h_drift wrapped into the periodic box (omega likewise), the
// walls moved by h_drift, then the clock at the step's end (next_step). A particle that is
// not finite or has left the box through a side neither periodic nor open ends the step
// there, before its evaluation (ParticleLost, naming it).
void drift_to_step_end(World& world, double h_kick, double h_drift);
// v <- v + F/m h (omega likewise). Both move only the particles the process owns.
void kick(World& world, double h);
// The clock after a step: world.step + 1, world.time = step dt.
void next_step(World& world);

// v <- v + F/m dt; x <- x + v dt (and the same for rotation); then new forces.
template <class Evaluate>
void symplectic_euler_step(World& world, Evaluate&& evaluate) {
  drift_to_step_end(world, world.dt, world.dt);
  evaluate(0.0);
}

// v <- v + F/m dt/2; x <- x + v dt; new forces; v <- v + F/m dt/2. The contacts' damping
// uses the half-step velocity, as LAMMPS and LIGGGHTS do; the still fluid's forces use the
// velocity extrapolated to the step's end, v + F/m dt/2 (fluid_lead = dt/2), which keeps
// them second order.
template <class Evaluate>
void velocity_verlet_step(World& world, Evaluate&& evaluate) {
  drift_to_step_end(world, 0.5 * world.dt, world.dt);
  evaluate(0.5 * world.dt);
  kick(world, 0.5 * world.dt);
}

// One fixed step of symplectic Euler or velocity Verlet.
template <class Evaluate>
void advance(Integrator integrator, World& world, Evaluate&& evaluate) {
  if (integrator == Integrator::symplectic_euler) symplectic_euler_step(world, evaluate);
  else velocity_verlet_step(world, evaluate);
}

}  // namespace tsubu
