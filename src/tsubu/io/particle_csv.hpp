// The particle state as CSV, in id order: `id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz` with
// units in the header (tsubu export; read back by [[particles]] source = "file").
#pragma once
#include <string>

#include "tsubu/world/particles.hpp"

namespace tsubu {

void write_particles_csv(const std::string& path, const Particles& p);

}  // namespace tsubu
