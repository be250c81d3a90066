// Triangle meshes for tests (test_mesh.cpp, test_mesh_walls.cpp, test_mesh_wall_rates.cpp,
// test_insertion.cpp): a flat plate, a pyramid, and a mesh wall of either.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "tsubu/world/mesh.hpp"

namespace tsubu::testing {

// A square plate of n x n cells of side h, each cut into two triangles along alternating
// diagonals (vertices shared by 4 or 8 triangles), mapped by f from the plane z = 0 (where
// its corner is the origin).
template <class Map>
TriangleMesh plate(int n, double h, Map f) {
  std::vector<Vec3> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) v.push_back(f(Vec3{i * h, j * h, 0}));
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      } else {
        t.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        t.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  return TriangleMesh(v, t);
}

// A pyramid's apex at the origin, its four faces sloping down at 20 degrees to 1 cm from it
// along x and y: faces, convex edges and a convex corner.
inline std::shared_ptr<const TriangleMesh> pyramid() {
  const double s = -std::tan(20 * M_PI / 180) * 0.01;
  return std::make_shared<const TriangleMesh>(
      std::vector<Vec3>{{0, 0, 0}, {0.01, -0.01, s}, {0.01, 0.01, s}, {-0.01, 0.01, s}, {-0.01, -0.01, s}},
      std::vector<std::array<std::uint32_t, 3>>{{{0, 1, 2}}, {{0, 2, 3}}, {{0, 3, 4}}, {{0, 4, 1}}});
}

// A wall of the mesh, where it was read, standing still.
inline Wall mesh_wall(std::shared_ptr<const TriangleMesh> mesh) {
  Wall w;
  w.shape = WallShape::mesh;
  w.mesh = std::move(mesh);
  return w;
}

}  // namespace tsubu::testing
