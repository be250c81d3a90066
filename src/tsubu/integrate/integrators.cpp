#include "tsubu/integrate/integrators.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "tsubu/core/error.hpp"
#include "tsubu/core/parallel.hpp"

namespace tsubu {

namespace {

// Throws ParticleLost naming the first particle that is not finite or has left the box, at
// the step the clock says.
[[noreturn]] void report_lost(const World& world) {
  const Particles& p = world.particles;
  std::size_t i = 0;
  while (i + 1 < p.size() && world.domain.kept(p.position[i]) && std::isfinite(p.position[i].x + p.position[i].y + p.position[i].z)) ++i;
  const Vec3 x = p.position[i], v = p.velocity[i];
  std::ostringstream msg;
  msg << "step " << world.step << ", t = " << world.time << " s: particle id " << p.id[i]
      << " left the domain or is not finite: x = (" << x.x << ", " << x.y << ", " << x.z << ") m, v = (" << v.x
      << ", " << v.y << ", " << v.z << ") m/s; a wall may be missing, or the time step " << world.dt
      << " s is too large";
  throw ParticleLost(msg.str());
}

// v <- v + F/m h_kick, x <- x + v h_drift wrapped into the periodic box (omega likewise), the
// walls moved by h_drift. Returns whether a particle is not finite or has left the box
// through a side neither periodic nor open.
bool kick_drift(World& world, double h_kick, double h_drift) {
  Particles& p = world.particles;
  const std::size_t n = world.owned();
  const int threads = threads_for(n);
  std::vector<char> lost(static_cast<std::size_t>(threads), 0);
  for_each_thread(threads, [&](int t) {
    const auto [begin, end] = static_range(n, t, threads);
    bool any = false;
    for (std::size_t i = begin; i < end; ++i) {
      p.velocity[i] += p.force[i] * (h_kick / p.translational_mass[i]);
      p.omega[i] += p.torque[i] * (h_kick / p.inertia[i]);
      const Vec3 x = world.domain.wrap(p.position[i] + p.velocity[i] * h_drift);
      p.position[i] = x;
      any |= !(world.domain.kept(x) && std::isfinite(x.x + x.y + x.z));
    }
    lost[static_cast<std::size_t>(t)] = any;
  });
  for (Wall& w : world.walls) w.advance(world.time, h_drift);
  return std::find(lost.begin(), lost.end(), 1) != lost.end();
}

}  // namespace

void drift_to_step_end(World& world, double h_kick, double h_drift) {
  const bool lost = kick_drift(world, h_kick, h_drift);
  next_step(world);
  if (lost) report_lost(world);
}

void kick(World& world, double h) {
  Particles& p = world.particles;
  parallel_for(world.owned(), [&](std::size_t i) {
    p.velocity[i] += p.force[i] * (h / p.translational_mass[i]);
    p.omega[i] += p.torque[i] * (h / p.inertia[i]);
  });
}

void next_step(World& world) {
  ++world.step;
  world.time = static_cast<double>(world.step) * world.dt;
}

}  // namespace tsubu
