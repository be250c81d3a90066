#include "tsubu/search/triangle_grid.hpp"

#include <algorithm>
#include <cmath>

namespace tsubu {

TriangleGrid::TriangleGrid(const TriangleMesh& mesh, double cell) {
  for (std::size_t t = 0; t < mesh.size(); ++t) boxes_.push_back(mesh.box(t));
  Vec3 upper = boxes_[0][1];
  lower_ = boxes_[0][0];
  for (const auto& [low, high] : boxes_)
    for (int a = 0; a < 3; ++a) lower_[a] = std::min(lower_[a], low[a]), upper[a] = std::max(upper[a], high[a]);
  cell_ = cell;
  for (;;) {
    long total = 1;
    for (int a = 0; a < 3; ++a) cells_[a] = std::max(1L, static_cast<long>(std::ceil((upper[a] - lower_[a]) / cell_))), total *= cells_[a];
    if (total <= kMaxCells) break;
    cell_ *= 2;
  }
  // Two passes over the triangles' boxes: count per cell, then fill.
  auto each_cell = [&](std::size_t t, auto&& f) {
    long first[3], last[3];
    for (int a = 0; a < 3; ++a) span(a, boxes_[t][0][a], boxes_[t][1][a], first[a], last[a]);
    for (long k = first[2]; k <= last[2]; ++k)
      for (long j = first[1]; j <= last[1]; ++j)
        for (long i = first[0]; i <= last[0]; ++i) f(index(i, j, k));
  };
  start_.assign(static_cast<std::size_t>(cells_[0] * cells_[1] * cells_[2]) + 1, 0);
  for (std::size_t t = 0; t < mesh.size(); ++t) each_cell(t, [&](long c) { ++start_[static_cast<std::size_t>(c) + 1]; });
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  members_.resize(start_.back());
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t t = 0; t < mesh.size(); ++t)
    each_cell(t, [&](long c) { members_[fill[static_cast<std::size_t>(c)]++] = static_cast<std::uint32_t>(t); });
}

double TriangleGrid::cell_for(const TriangleMesh& mesh, double width) {
  double size = 0;
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const Vec3 extent = mesh.box(t)[1] - mesh.box(t)[0];
    size += std::max({extent.x, extent.y, extent.z});
  }
  return std::max(width, size / static_cast<double>(mesh.size()));
}

bool TriangleGrid::span(int a, double low, double high, long& first, long& last) const {
  const double from = std::floor((low - lower_[a]) / cell_), to = std::floor((high - lower_[a]) / cell_);
  if (!(to >= 0) || !(from < static_cast<double>(cells_[a]))) return false;  // misses the grid (or NaN)
  first = std::max(0L, static_cast<long>(from));
  last = std::min(cells_[a] - 1, static_cast<long>(to));
  return true;
}

void TriangleGrid::near(const Vec3& x, double reach, std::vector<std::uint32_t>& out) const {
  long first[3], last[3];
  for (int a = 0; a < 3; ++a)
    if (!span(a, x[a] - reach, x[a] + reach, first[a], last[a])) return;
  const std::size_t begin = out.size();
  for (long k = first[2]; k <= last[2]; ++k)
    for (long j = first[1]; j <= last[1]; ++j)
      for (long i = first[0]; i <= last[0]; ++i) {
        const auto c = static_cast<std::size_t>(index(i, j, k));
        for (std::uint32_t s = start_[c]; s < start_[c + 1]; ++s)
          if (grown_box_holds(boxes_[members_[s]], x, reach)) out.push_back(members_[s]);
      }
  std::sort(out.begin() + static_cast<long>(begin), out.end());
  out.erase(std::unique(out.begin() + static_cast<long>(begin), out.end()), out.end());
}

std::optional<TriangleDistance> TriangleGrid::nearest_within(const TriangleMesh& mesh, const Vec3& x, double reach,
                                                             std::vector<std::uint32_t>& scratch) const {
  scratch.clear();
  near(x, reach, scratch);  // only triangles whose grown boxes hold x
  std::optional<TriangleDistance> best;
  for (std::uint32_t t : scratch) {
    const double d = norm(x - mesh.nearest(t, x).point);
    if (d < reach && (!best || d < best->distance)) best = TriangleDistance{t, d};
  }
  return best;
}

}  // namespace tsubu
