// The box cut into a Cartesian grid of subdomains, one per process (docs/parallel.md): the
// process that owns a position, and the processes near it.
#pragma once
#include <array>
#include <vector>

#include "tsubu/core/vec3.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

class RankGrid {
 public:
  // `processes` subdomains of equal size: along x, y and z the `counts` given, 0 along an
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
  // The narrowest subdomain along an axis that is cut, or infinity when none is.
  double narrowest() const;

 private:
  Domain domain_;
  std::array<int, 3> counts_{1, 1, 1};
  static bool matches(const std::array<int, 3>& grid, const std::array<int, 3>& counts);
  int cell(int axis, double x) const;
  int rank_of(const std::array<int, 3>& c) const { return c[0] + counts_[0] * (c[1] + counts_[1] * c[2]); }
};

}  // namespace tsubu
