// A mesh's triangles binned in a uniform grid over its bounding box, for the triangles near a
// point: a large mesh costs per triangle near the grains, not per triangle.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/world/mesh.hpp"

namespace tsubu {

class TriangleGrid {
 public:
  // Cells at least `cell` wide (wider where the mesh would need more than kMaxCells).
  TriangleGrid(const TriangleMesh& mesh, double cell);

  // Appends to `out` the triangles whose bounding boxes come within `reach` of x (in the
  // mesh's frame), in ascending order, each once.
  void near(const Vec3& x, double reach, std::vector<std::uint32_t>& out) const;

  static constexpr long kMaxCells = 1L << 22;

 private:
  Vec3 lower_;
  double cell_ = 0;
  long cells_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_, members_;  // cell c's triangles: members_[start_[c] .. start_[c + 1])

  long index(long i, long j, long k) const { return (k * cells_[1] + j) * cells_[0] + i; }
  // The range of cells along axis a that [low, high] covers, clamped to the grid; empty when
  // it misses the grid.
  bool span(int a, double low, double high, long& first, long& last) const;
};

}  // namespace tsubu
