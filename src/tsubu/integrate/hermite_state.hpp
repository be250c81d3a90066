// The per-particle state of the block-step Hermite integrator (spec: docs/integrators.md):
// each particle's own time and level, and the accelerations and their rates of its last
// evaluation. Owned by the stepper, not by Particles; permuted with the particles when they
// are renumbered.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

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

// A particle's kinematics at an evaluation time, with the rates the contact laws need.
struct Kinematics {
  Vec3 x, v, w;      // position, velocity, spin
  Vec3 a, alpha;     // dv/dt, domega/dt
};

// Every particle predicted from its own time to `now` by its Taylor series (spec section 1,
// predictor): x_p = x + v tau + a tau^2/2 + j tau^3/6, v_p = v + a tau + j tau^2/2,
// omega_p = omega + alpha tau + alpha_dot tau^2/2; the rates at `now` are a + j tau and
// alpha + alpha_dot tau. Positions are wrapped into the periodic box.
struct Predictor {
  const Particles& p;
  const HermiteState& s;
  const Domain& domain;
  std::int64_t now = 0;  // ticks
  double tick = 0;       // s

  Kinematics at(std::size_t i) const {
    const double tau = static_cast<double>(now - s.time[i]) * tick;
    const Vec3 &a = s.acc[i], &j = s.jerk[i], &al = s.alpha[i], &ad = s.alpha_dot[i];
    Kinematics k;
    k.x = domain.wrap(p.position[i] + tau * (p.velocity[i] + tau * (0.5 * a + (tau / 6.0) * j)));
    k.v = p.velocity[i] + tau * (a + (0.5 * tau) * j);
    k.w = p.omega[i] + tau * (al + (0.5 * tau) * ad);
    k.a = a + tau * j;
    k.alpha = al + tau * ad;
    return k;
  }
};

}  // namespace tsubu
