#include "tsubu/source/insertion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tsubu/core/random.hpp"
#include "tsubu/source/release.hpp"
#include "tsubu/source/size_moments.hpp"

namespace tsubu {

namespace {

// The corners of the region's bounding box.
std::pair<Vec3, Vec3> bounds(const InsertionRegion& r) {
  if (r.shape == InsertionRegion::Shape::box) return {r.lower, r.upper};
  const Vec3 u = perpendicular(r.axis), v = cross(r.axis, u), end = r.point + r.length * r.axis;
  Vec3 lo, hi;
  for (int k = 0; k < 3; ++k) {
    const double reach = r.radius * std::hypot(u[k], v[k]);
    lo[k] = std::min(r.point[k], end[k]) - reach;
    hi[k] = std::max(r.point[k], end[k]) + reach;
  }
  return {lo, hi};
}

}  // namespace

double Insertion::grains_per_second() const { return mass_rate / (density * mean_grain_volume(sizes)); }

InsertionStream::InsertionStream(const Insertion& insertion, std::uint64_t seed)
    : insertion_(insertion), seed_(mix64(seed ^ 0x15e27105eedULL)) {}

double InsertionStream::diameter(std::int64_t serial) const {
  Random rng(mix64(seed_ + mix64(static_cast<std::uint64_t>(serial))));
  return insertion_.sizes.sample(rng);
}

std::vector<NewGrain> InsertionStream::due(double t) {
  std::vector<NewGrain> out = waiting_at(state_, t);
  while (!state_.limit_reached) {
    const double arrival =
        insertion_.mass_rate > 0 ? insertion_.start + state_.mass_released / insertion_.mass_rate : insertion_.start;
    if (arrival > t) break;
    const double d = diameter(state_.next);
    if (!release(state_, {state_.next, d, 0, 0, arrival, {}, 0}, grain_mass(insertion_.density, d), insertion_.mass_limit, out))
      break;
  }
  return out;
}

void InsertionStream::delay(NewGrain g) { turn_back(state_, g); }

Vec3 InsertionStream::position(const NewGrain& g, double) const {
  // Each try of each grain its own stream: the place does not depend on the order of tries.
  Random rng(mix64(seed_ + mix64(static_cast<std::uint64_t>(g.serial)) + mix64(0x7e57ULL + static_cast<std::uint64_t>(g.delays))));
  const InsertionRegion& r = insertion_.region;
  const double radius = 0.5 * g.diameter;
  if (r.shape == InsertionRegion::Shape::box)
    return {rng.uniform(r.lower.x + radius, r.upper.x - radius), rng.uniform(r.lower.y + radius, r.upper.y - radius),
            rng.uniform(r.lower.z + radius, r.upper.z - radius)};
  const Vec3 u = perpendicular(r.axis), v = cross(r.axis, u);
  const double rho = (r.radius - radius) * std::sqrt(rng.uniform()), phi = 2 * M_PI * rng.uniform();
  const double along = rng.uniform(radius, r.length - radius);
  return r.point + along * r.axis + rho * (std::cos(phi) * u + std::sin(phi) * v);
}

bool InsertionStream::clear_of_walls(const Vec3& x, double radius, std::span<const Wall> walls) {
  return std::all_of(walls.begin(), walls.end(), [&](const Wall& w) {
    if (!w.mesh) return w.touch(x).distance >= radius;
    return !grid_of(w.mesh).nearest_within(*w.mesh, w.to_mesh(x), radius, near_);  // two-sided: no "behind"
  });
}

const TriangleGrid& InsertionStream::grid_of(const std::shared_ptr<const TriangleMesh>& mesh) {
  for (const MeshGrid& g : mesh_grids_)
    if (g.mesh == mesh) return *g.grid;
  const double cell = TriangleGrid::cell_for(*mesh, insertion_.sizes.largest());
  return *mesh_grids_.emplace_back(MeshGrid{mesh, std::make_shared<const TriangleGrid>(*mesh, cell)}).grid;
}

SphereGrid InsertionStream::neighbours(const Domain& domain, std::span<const Vec3> position, std::span<const double> radius,
                                       const std::vector<NewGrain>& due, double) const {
  double entering = 0;
  for (const NewGrain& g : due) entering = std::max(entering, 0.5 * g.diameter);
  auto [lo, hi] = bounds(insertion_.region);
  std::array<bool, 3> wrap{};
  for (int k = 0; k < 3; ++k)
    if (domain.periodic[k]) wrap[k] = true, lo[k] = domain.lower[k], hi[k] = domain.upper[k];  // images across the sides
  std::vector<std::size_t> near;
  double r_max = entering;
  for (std::size_t i = 0; i < position.size(); ++i) {
    bool reaches = true;
    for (int k = 0; k < 3; ++k)
      if (!wrap[k] && (position[i][k] + radius[i] < lo[k] - entering || position[i][k] - radius[i] > hi[k] + entering))
        reaches = false;
    if (reaches) near.push_back(i), r_max = std::max(r_max, radius[i]);
  }
  SphereGrid grid(domain, lo, hi, wrap, entering + r_max);
  for (std::size_t i : near) grid.add(position[i], radius[i]);
  return grid;
}

void InsertionStream::restore(const State& s) {
  if (s.next < 0 || s.released != s.next)
    throw std::runtime_error("insertion state: grain " + std::to_string(s.next) + " does not follow " +
                             std::to_string(s.released) + " released");
  state_ = s;
}

std::vector<std::pair<std::string, double>> insertion_rates(const Insertion& i) {
  return {{"inflow_F", i.mass_rate}, {"inflow_grains_per_s", i.grains_per_second()}};
}

}  // namespace tsubu
