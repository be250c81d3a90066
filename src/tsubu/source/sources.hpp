// Particle sources: each appends grains (diameter, position, velocity) with the location they
// came from, so that later checks can name the CSV line or the scenario table.
#pragma once
#include <istream>
#include <string>
#include <vector>

#include "tsubu/core/random.hpp"
#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

struct Grain {
  Vec3 position, velocity;
  double diameter = 0;
  SourceLocation where;
  Vec3 omega;         // rad/s, initial spin (file sources; zero otherwise)
  int material = -1;  // file sources: the row's material; -1: the source's
};

// The most particles a run may hold on this machine: its physical memory over a generous
// estimate of what one particle costs with its contacts. Sources refuse to create more.
std::size_t particle_limit();
inline constexpr std::size_t kBytesPerParticle = 2048;

// CSV `x,y,z,d[,vx,vy,vz]`, SI units, optional header line. Errors name file:line.
std::vector<Grain> read_csv_grains(const ParticleSource& src);
// The same from a stream; `name` is the file name the errors give.
std::vector<Grain> parse_csv_grains(std::istream& in, const std::string& name);

// The particle state `tsubu export` writes: `id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz`
// (SI units, material = index into the scenario's [[materials]], `materials` of them), one
// header line. Errors name file:line and the column.
std::vector<Grain> read_state_grains(const ParticleSource& src, std::size_t materials);
std::vector<Grain> parse_state_grains(std::istream& in, const std::string& name, std::size_t materials);

// Simple cubic lattice filling [lower, upper] with `spacing` between centres.
std::vector<Grain> lattice_grains(const ParticleSource& src);

// Random sequential placement without overlap in [lower, upper] (centres at least a radius
// inside the region, except along periodic axes spanning the whole domain), up to the solid
// fraction, largest grains first.
std::vector<Grain> random_grains(const ParticleSource& src, const Domain& domain, Random& rng);

}  // namespace tsubu
