#include "tsubu/search/sphere_grid.hpp"

#include <algorithm>

namespace tsubu {

SphereGrid::SphereGrid(const Domain& domain, const Vec3& lower, const Vec3& upper, const std::array<bool, 3>& wrap,
                       double reach)
    : domain_(domain), lower_(lower), extent_(upper - lower), wrap_(wrap) {
  // At most 2^20 cells an axis (a degenerate reach must not overflow the cell keys).
  for (int k = 0; k < 3; ++k) cells_[k] = static_cast<int>(std::clamp(extent_[k] / reach, 1.0, 1024.0 * 1024));
}

int SphereGrid::cell_of(const Vec3& x, int k) const {
  return std::clamp(static_cast<int>((x[k] - lower_[k]) / extent_[k] * cells_[k]), 0, cells_[k] - 1);
}

void SphereGrid::add(const Vec3& x, double radius) {
  members_[key(cell_of(x, 0), cell_of(x, 1), cell_of(x, 2))].push_back(radius_.size());
  position_.push_back(x);
  radius_.push_back(radius);
}

bool SphereGrid::overlaps(const Vec3& x, double radius) const {
  const int c[3] = {cell_of(x, 0), cell_of(x, 1), cell_of(x, 2)};
  // With fewer than 3 cells along a wrapped axis the stencil repeats cells; harmless.
  for (int dk = -1; dk <= 1; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        int ci[3] = {c[0] + di, c[1] + dj, c[2] + dk};
        bool outside = false;
        for (int k = 0; k < 3; ++k) {
          if (wrap_[k]) ci[k] = (ci[k] + cells_[k]) % cells_[k];
          else if (ci[k] < 0 || ci[k] >= cells_[k]) outside = true;
        }
        if (outside) continue;
        const auto it = members_.find(key(ci[0], ci[1], ci[2]));
        if (it == members_.end()) continue;
        for (std::size_t m : it->second) {
          const double reach = radius + radius_[m];
          if (norm2(domain_.separation(x, position_[m])) < reach * reach) return true;
        }
      }
  return false;
}

}  // namespace tsubu
