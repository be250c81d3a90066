// The per-particle state of the block-step Hermite integrator (spec: docs/integrators.md):
// each particle's own time and level, and the accelerations and their rates of its last
// evaluation. Owned by the stepper, not by Particles; permuted with the particles when they
// are renumbered.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/core/vec3.hpp"

namespace tsubu {

struct HermiteState {
  std::vector<std::int64_t> time;   // ticks; the particle's position and velocity are at this time
  std::vector<std::uint8_t> level;  // step = dt / 2^level
  std::vector<Vec3> acc, jerk;      // a = F/m and da/dt at `time`
  std::vector<Vec3> alpha, alpha_dot;  // domega/dt and its rate at `time`

  std::size_t size() const { return time.size(); }
  void resize(std::size_t n) {
    time.resize(n), level.resize(n), acc.resize(n), jerk.resize(n), alpha.resize(n), alpha_dot.resize(n);
  }
  // f(array) for every array, always in this order (the checkpoint format's).
  template <class F>
  void for_each_array(F&& f) { each_array(*this, f); }
  template <class F>
  void for_each_array(F&& f) const { each_array(*this, f); }

 private:
  template <class Self, class F>
  static void each_array(Self& s, F& f) {
    f(s.time), f(s.level), f(s.acc), f(s.jerk), f(s.alpha), f(s.alpha_dot);
  }
};

}  // namespace tsubu
