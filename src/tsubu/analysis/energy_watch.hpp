// Stops a run whose total energy grows although nothing does work on it: the sign of a time
// step too large for the contact stiffness (docs/reliability.md).
#pragma once
#include "tsubu/model/model.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// Throws NumericalError naming the first particle whose kinetic energy is not a finite
// double (a speed or spin beyond about 1e150 in SI units), or the sum that is not: every
// energy in series.csv, and the growth check below (inf - inf), would be meaningless.
void require_finite_energies(const World& world, const Vec3& gravity, double elastic_energy);

class EnergyWatch {
 public:
  // `limit`: the allowed growth of the total energy E = kinetic + rotational + gravitational +
  // elastic above its first observed value, as a fraction of the largest kinetic + elastic
  // energy seen; 0 turns the check off. It also stays off where work may be done on the
  // particles: moving walls, a fluid, or gravity along a periodic axis.
  EnergyWatch(const World& world, const Model& model, double limit);

  // Throws NumericalError when an energy is not finite (require_finite_energies, whatever
  // the limit) or the growth exceeds the limit.
  void observe(const World& world, double elastic_energy);

  // The state to carry over a checkpoint: the reference energy and the largest active energy.
  struct State {
    bool started = false;
    double reference = 0, active_max = 0;
  };
  const State& state() const { return state_; }
  void restore(const State& s) { state_ = s; }

 private:
  bool on_ = false;
  double limit_ = 0;
  Vec3 gravity_;  // m/s^2
  State state_;
};

}  // namespace tsubu
