// Grains inserted into a region during the run (source = "insertion", docs/scenario.md): a
// hopper filled from above, a drum fed, a chute supplied. Grain j of the source has its own
// random stream (the seed and j): its diameter, drawn from the size distribution, and its
// place, drawn at random in the region with its centre at least its radius inside the
// region, again at each try. It is due at t_j = start + M_j / mass_rate, M_j the mass of the
// grains before it (all at `start` without a rate), and is released while the mass released
// stays within mass_limit. A grain whose place is taken (it would overlap a particle or
// stand within its radius of a wall) waits and is tried again at the next step at a new
// place: never dropped, never overlapped, as the inflow's grains (source/inflow.hpp). A mesh
// wall is two-sided: a place within its radius of any of its triangles is taken, from
// either side.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/core/size_distribution.hpp"
#include "tsubu/core/vec3.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/search/sphere_grid.hpp"
#include "tsubu/search/triangle_grid.hpp"
#include "tsubu/source/inflow.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

struct Insertion {
  InsertionRegion region;
  SizeDistribution sizes;
  double density = 0;     // kg/m^3
  double mass_rate = 0;   // kg/s; 0: the whole mass_limit at `start`
  double mass_limit = 0;  // kg; 0: none
  double start = 0;       // s
  Vec3 velocity;          // m/s, of every grain as it is placed

  double grains_per_second() const;  // mass_rate / (rho pi/6 E[d^3])
};

class InsertionStream {
 public:
  using State = InflowStream::State;  // slab unused; next: the serial of the next grain

  InsertionStream(const Insertion& insertion, std::uint64_t seed);

  const Insertion& insertion() const { return insertion_; }

  // The grains due by time t: first those waiting (their arrival set to t), then the new
  // ones with t_j <= t in order, while the mass released stays within the limit.
  std::vector<NewGrain> due(double t);
  // A grain of due() whose place is taken: it waits for the next due(), at a new place.
  void delay(NewGrain g);

  // The place of this try of grain g (its serial and delays so far).
  Vec3 position(const NewGrain& g, double t) const;
  Vec3 velocity() const { return insertion_.velocity; }
  double density() const { return insertion_.density; }
  // Within its radius of a wall (or behind one), a grain's place is taken; of a mesh, within
  // its radius of a triangle, where the mesh is at this time (Wall::to_mesh).
  bool clear_of_walls(const Vec3& x, double radius, std::span<const Wall> walls);
  // The particles an entering grain could overlap (those reaching into the region), ready for
  // overlaps(x, r); the domain gives the periodic sides.
  SphereGrid neighbours(const Domain& domain, std::span<const Vec3> position, std::span<const double> radius,
                        const std::vector<NewGrain>& due, double t) const;

  // The mass limit has stopped the source and no grain is waiting.
  bool exhausted() const { return state_.limit_reached && state_.waiting.empty(); }
  const State& state() const { return state_; }
  void restore(const State& s);

 private:
  Insertion insertion_;
  std::uint64_t seed_;
  State state_;
  // The grid of each mesh met in clear_of_walls, built at its first use (cells a largest
  // grain or a triangle wide); shared by copies of the stream.
  struct MeshGrid {
    std::shared_ptr<const TriangleMesh> mesh;
    std::shared_ptr<const TriangleGrid> grid;
  };
  std::vector<MeshGrid> mesh_grids_;
  std::vector<std::uint32_t> near_;  // scratch of clear_of_walls

  const TriangleGrid& grid_of(const std::shared_ptr<const TriangleMesh>& mesh);

  double diameter(std::int64_t serial) const;
};

// Named values for run.json and `tsubu check`: inflow_F (the mass rate, kg/s; 0 for all at
// once) and inflow_grains_per_s.
std::vector<std::pair<std::string, double>> insertion_rates(const Insertion& i);

}  // namespace tsubu
