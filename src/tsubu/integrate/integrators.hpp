// Fixed-step integrators with rotation. Both expect world.particles.force/torque to hold
// the forces at the current state when called (ForceField::compute once before the loop).
#pragma once
#include <string>

#include "tsubu/forces/force_field.hpp"

namespace tsubu {

// block_hermite: BlockHermite (block_hermite.hpp), not a fixed-step scheme.
enum class Integrator { symplectic_euler, velocity_verlet, block_hermite };

// The scenario's name of an integrator (simulation.integrator).
inline const char* integrator_name(Integrator i) {
  switch (i) {
    case Integrator::symplectic_euler: return "symplectic_euler";
    case Integrator::velocity_verlet: return "velocity_verlet";
    case Integrator::block_hermite: return "block_hermite";
  }
  return "";
}

// Forces are divided by the translational mass (mass plus the fluid's added mass).
// v <- v + F/m dt; x <- x + v dt (and the same for rotation); then new forces.
void symplectic_euler_step(World& world, ForceField& forces);

// v <- v + F/m dt/2; x <- x + v dt; new forces; v <- v + F/m dt/2. The contacts' damping
// uses the half-step velocity, as LAMMPS and LIGGGHTS do; the still fluid's forces use the
// velocity extrapolated to the step's end, v + F/m dt/2 (ForceField::compute), which keeps
// them second order.
void velocity_verlet_step(World& world, ForceField& forces);

// One fixed step of symplectic Euler or velocity Verlet.
inline void advance(Integrator integrator, World& world, ForceField& forces) {
  if (integrator == Integrator::symplectic_euler) symplectic_euler_step(world, forces);
  else velocity_verlet_step(world, forces);
}

}  // namespace tsubu
