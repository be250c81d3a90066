// The box cut into a Cartesian grid of subdomains, one per process (docs/parallel.md): the
// process that owns a position, and the processes near it. The cuts along each axis start
// evenly spaced and move with the work (balance): every slab between two cuts of an axis
// holds an equal share of it.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "tsubu/core/vec3.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

class RankGrid {
 public:
  // `processes` subdomains, first of equal size: along x, y and z the `counts` given, 0 along an
  // axis for an automatic count; of the grids that match them, the one whose subdomains have
  // the least surface (ties: the fewest cuts along x, then along y). Throws std::invalid_argument when
  // no grid of `processes` subdomains matches them (see fits).
  RankGrid(const Domain& domain, int processes, std::array<int, 3> counts = {0, 0, 0});
  // Whether some grid of `processes` subdomains has the `counts` given (0: any).
  static bool fits(const std::array<int, 3>& counts, int processes);

  const std::array<int, 3>& counts() const { return counts_; }
  // The process whose subdomain holds x (a position outside a closed side belongs to the
  // subdomain at that side).
  int owner(const Vec3& x) const;
  // The processes whose subdomain, widened by `width` on every side, holds x or one of its
  // periodic images: each once, in rank order, `skip` left out.
  void near(const Vec3& x, double width, int skip, std::vector<int>& out) const;
  // The positions of the cuts along an axis: counts()[axis] + 1 of them, ascending, from the
  // box's lower side to its upper side.
  const std::vector<double>& cuts(int axis) const { return cuts_[static_cast<std::size_t>(axis)]; }

  // Work is counted in bins of equal width along each axis, kBinsPerSlab per slab of the
  // first, even cuts; a cut moves from bin edge to bin edge.
  static constexpr int kBinsPerSlab = 64;
  int bins(int axis) const { return kBinsPerSlab * counts_[static_cast<std::size_t>(axis)]; }
  // The bin of x along an axis (a position outside the box in the bin at that side).
  int bin(int axis, double x) const;
  // Moves the cuts of every axis that is cut so that each slab between two cuts holds as
  // nearly as the bins allow an equal share of `work` (per axis, per bin, bins(axis) of them,
  // the work of the whole box: the same on every process), each slab at least one bin wide.
  // An axis with no work keeps its cuts.
  void balance(const std::array<std::vector<std::int64_t>, 3>& work);

 private:
  Domain domain_;
  std::array<int, 3> counts_{1, 1, 1};
  std::array<std::vector<double>, 3> cuts_;
  static bool matches(const std::array<int, 3>& grid, const std::array<int, 3>& counts);
  double bin_edge(int axis, int edge) const;
  int cell(int axis, double x) const;
  int rank_of(const std::array<int, 3>& c) const { return c[0] + counts_[0] * (c[1] + counts_[1] * c[2]); }
};

}  // namespace tsubu
