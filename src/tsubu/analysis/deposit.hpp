// Measurements on a deposit of spheres, after the sedimentation experiment
// (docs/sedimentation.md): deposit height, porosity by
// Monte Carlo and by exact sphere-slab volumes, coordination with both rattler definitions,
// and the share of small grains in a layer. Pure functions of positions, radii and contact
// counts: the box's x-y cross-section is the measured area; grains are whole spheres (a
// periodic box wraps them across its sides, so only the z limits cut them).
#pragma once
#include <cstdint>
#include <span>

#include "tsubu/core/vec3.hpp"
#include "tsubu/scenario/deposit_rules.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

// Grains in a box: index-aligned centres and radii.
struct Packing {
  Domain domain;
  std::span<const Vec3> position;  // m
  std::span<const double> radius;  // m

  double base_area() const { return domain.length(0) * domain.length(1); }
};

// Solid volume in the slab a < z < b: the sum of the exact sphere-slab volumes (caps).
double solid_volume(const Packing& p, double a, double b);

// solid_volume over the slab's volume (full x-y cross-section).
double solid_fraction(const Packing& p, double a, double b);

// Grains with their centre in a < z < b.
long grains_in_slab(std::span<const Vec3> position, double a, double b);

// The deposit's surface by the surface rule (scenario/deposit_rules.hpp).
double surface_height(const Packing& p, const SurfaceRule& rule);

// The deposit height by the paper's slice rule (scenario/deposit_rules.hpp).
double deposit_height(const Packing& p, const SliceRule& rule);

// Porosity 1 - phi of a < z < b as the fraction of `points` uniformly random points
// (from the seed) that lie in no grain, with its binomial standard error
// sqrt(lambda (1 - lambda) / points); 0.25/points bounds its square, so 65536 points give
// an error below 0.002. Points are tested against the grains near them only (a cell grid).
// Throws StopRequested when SIGINT/SIGTERM asks a run to stop (core/stop_signal.hpp).
struct PorosityEstimate {
  double porosity = 1;
  double standard_error = 0;
  long points = 0;
};
PorosityEstimate porosity_monte_carlo(const Packing& p, double a, double b, long points, std::uint64_t seed);

// Mean coordination number Z of the grains with centre in a < z < b from their
// particle-particle contact counts (walls excluded): all of them, and without rattlers by
// the geometric definition (fewer than 2 contacts) and by the mechanical one for frictional
// spheres (fewer than 4). A mean over no grain is 0.
struct Coordination {
  double all = 0, without_rattlers_2 = 0, without_rattlers_4 = 0;
  long grains = 0, rattlers_2 = 0, rattlers_4 = 0;
};
Coordination coordination_numbers(std::span<const Vec3> position, std::span<const int> pair_contacts, double a, double b);

// Segregation Gamma: the share of grains with diameter below `small_diameter` (d_max/3 in
// the experiment) in the solid volume of a < z < b (exact slab volumes); 0 for a layer without
// solid.
double small_grain_share(const Packing& p, double a, double b, double small_diameter);

}  // namespace tsubu
