// The particles' motion at an evaluation time, as the block-step force evaluation reads it:
// each particle predicted from its own time by its Taylor series (docs/integrators.md,
// predictor). The block-step stepper (integrate/block_hermite) owns the times and the rates;
// the force field reads them through this view.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

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
  const Domain& domain;
  // Each particle's own time (ticks) and, at it, a = F/m, da/dt, domega/dt and its rate.
  const std::vector<std::int64_t>& time;
  const std::vector<Vec3>& acc;
  const std::vector<Vec3>& jerk;
  const std::vector<Vec3>& alpha;
  const std::vector<Vec3>& alpha_dot;
  std::int64_t now = 0;  // ticks
  double tick = 0;       // s
  // Predictions already made at `now` (the stepper's, each particle predicted once per block
  // time): entry i holds particle i's when cached_at[i] == now. Null: none.
  const Kinematics* cached = nullptr;
  const std::int64_t* cached_at = nullptr;

  // Seconds from tick t to now.
  double since(std::int64_t t) const { return static_cast<double>(now - t) * tick; }

  Kinematics at(std::size_t i) const {
    if (cached && cached_at[i] == now) return cached[i];
    const double tau = since(time[i]);
    const Vec3 &a = acc[i], &j = jerk[i], &al = alpha[i], &ad = alpha_dot[i];
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
