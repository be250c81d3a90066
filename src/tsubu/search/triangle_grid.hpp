// A mesh's triangles binned in a uniform grid over its bounding box, for the triangles near a
// point: a large mesh costs per triangle near the grains, not per triangle.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "tsubu/world/mesh.hpp"

namespace tsubu {

// A triangle of a mesh and the distance of a point from it (from its nearest point), m.
struct TriangleDistance {
  std::uint32_t triangle = 0;
  double distance = 0;
};

class TriangleGrid {
 public:
  // Cells at least `cell` wide (wider where the mesh would need more than kMaxCells).
  TriangleGrid(const TriangleMesh& mesh, double cell);
  // The cell for queries `width` wide: that or the mesh's mean triangle, whichever is larger
  // (a query visits a few cells, and a triangle lies in a few).
  static double cell_for(const TriangleMesh& mesh, double width);

  // Appends to `out` the triangles whose bounding boxes come within `reach` of x (in the
  // mesh's frame; grown_box_holds), in ascending order, each once.
  void near(const Vec3& x, double reach, std::vector<std::uint32_t>& out) const;
  // The triangle of `mesh` (the grid's) nearest to x (in the mesh's frame) of those nearer
  // than `reach`, the lowest index of equals; none when no triangle is. A point farther than
  // `reach` from the mesh's box, or from a triangle's box, looks no further at it. `scratch`
  // holds the candidates.
  std::optional<TriangleDistance> nearest_within(const TriangleMesh& mesh, const Vec3& x, double reach,
                                                 std::vector<std::uint32_t>& scratch) const;

  static constexpr long kMaxCells = 1L << 22;

 private:
  Vec3 lower_;
  double cell_ = 0;
  long cells_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_, members_;  // cell c's triangles: members_[start_[c] .. start_[c + 1])
  std::vector<std::array<Vec3, 2>> boxes_;        // per triangle, its bounding box (TriangleMesh::box)

  long index(long i, long j, long k) const { return (k * cells_[1] + j) * cells_[0] + i; }
  // The range of cells along axis a that [low, high] covers, clamped to the grid; empty when
  // it misses the grid.
  bool span(int a, double low, double high, long& first, long& last) const;
};

}  // namespace tsubu
