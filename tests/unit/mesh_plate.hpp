// A flat triangle mesh for tests (test_mesh.cpp, test_mesh_walls.cpp, test_insertion.cpp).
#pragma once
#include <array>
#include <cstdint>
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

}  // namespace tsubu::testing
