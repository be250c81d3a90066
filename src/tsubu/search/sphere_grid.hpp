// Spheres binned in a grid of cells, for the question "does this sphere (or point) overlap
// any sphere stored so far?": random placement without overlap, the inflow's entry check
// and the Monte Carlo porosity. Insertion and queries interleave freely (no rebinning).
#pragma once
#include <array>
#include <unordered_map>
#include <vector>

#include "tsubu/world/domain.hpp"

namespace tsubu {

class SphereGrid {
 public:
  // Cells over [lower, upper], at least `reach` wide: the largest sum of two radii a query
  // compares (a point query: the largest radius). Along an axis with wrap[k] the grid wraps
  // (the region spans the domain's periodic length there); along the others, positions
  // outside the region fall into its edge cells. Distances are the domain's minimum image.
  SphereGrid(const Domain& domain, const Vec3& lower, const Vec3& upper, const std::array<bool, 3>& wrap, double reach);

  void add(const Vec3& x, double radius);

  // True when a sphere of this radius at x is closer than the sum of radii to a stored
  // sphere (touching is not overlapping); radius 0 asks whether the point x is inside one.
  bool overlaps(const Vec3& x, double radius) const;

  std::size_t size() const { return radius_.size(); }

 private:
  Domain domain_;
  Vec3 lower_, extent_;
  std::array<bool, 3> wrap_;
  int cells_[3];
  std::unordered_map<long, std::vector<std::size_t>> members_;  // cell key -> sphere indices
  std::vector<Vec3> position_;
  std::vector<double> radius_;

  int cell_of(const Vec3& x, int k) const;
  long key(int i, int j, int k) const { return (static_cast<long>(k) * cells_[1] + j) * cells_[0] + i; }
};

}  // namespace tsubu
