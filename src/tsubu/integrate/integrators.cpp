#include "tsubu/integrate/integrators.hpp"

#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/core/parallel.hpp"

namespace tsubu {

namespace {

void kick(Particles& p, double h) {
  parallel_for(p.size(), [&](std::size_t i) {
    p.velocity[i] += p.force[i] * (h / p.translational_mass[i]);
    p.omega[i] += p.torque[i] * (h / p.inertia[i]);
  });
}

// x <- x + v dt, wrapped into the periodic box. A particle that is not finite or has left
// a non-periodic side of the box stops the run.
void drift(World& world, double h) {
  Particles& p = world.particles;
  parallel_for(p.size(), [&](std::size_t i) { p.position[i] = world.domain.wrap(p.position[i] + p.velocity[i] * h); });
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 x = p.position[i], v = p.velocity[i];
    if (world.domain.inside(x) && std::isfinite(x.x + x.y + x.z)) continue;
    std::ostringstream msg;
    msg << "step " << world.step << ", t = " << world.time << " s: particle id " << p.id[i]
        << " left the domain or is not finite: x = (" << x.x << ", " << x.y << ", " << x.z << ") m, v = (" << v.x
        << ", " << v.y << ", " << v.z << ") m/s; a wall may be missing, or the time step " << world.dt
        << " s is too large";
    throw NumericalError(msg.str());
  }
  for (Wall& w : world.walls) w.advance(world.time, h);
}

}  // namespace

void symplectic_euler_step(World& world, ForceField& forces) {
  kick(world.particles, world.dt);
  drift(world, world.dt);
  ++world.step;
  world.time = static_cast<double>(world.step) * world.dt;
  forces.compute(world);
}

void velocity_verlet_step(World& world, ForceField& forces) {
  kick(world.particles, 0.5 * world.dt);
  drift(world, world.dt);
  ++world.step;
  world.time = static_cast<double>(world.step) * world.dt;
  forces.compute(world);
  kick(world.particles, 0.5 * world.dt);
}

}  // namespace tsubu
