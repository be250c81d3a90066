// Everything a run evolves: box, walls, particles, contacts with their histories, clock.
// The physics that acts on it (materials, laws, gravity, fluid, search) is the Model
// (model/model.hpp), beside it.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "tsubu/world/contact_list.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/mesh.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

// Where a particle of radius r centred at x, given in the mesh's frame (Wall::to_mesh),
// touches triangle t of the mesh wall `wall`, its normal in the box's frame; false when the
// triangle does not count the contact or is surely out of reach (TriangleMesh::touch).
inline bool touch_triangle(const Wall& wall, std::uint32_t t, const Vec3& x, double r, WallTouch& out) {
  if (!wall.mesh->touch(t, x, r, out)) return false;
  out.normal = wall.from_mesh(out.normal);
  return true;
}

struct World {
  Domain domain;
  std::vector<Wall> walls;
  Particles particles;
  double dt = 0;           // s
  double time = 0;         // s
  std::int64_t step = 0;
  ContactList contacts;  // neighbour lists with their histories (world/contact_list.hpp)
  // A run split among processes (ranks/decomposition.hpp): the last `ghosts` particles are
  // copies of other processes' particles, which those integrate; 0 in one process.
  std::size_t ghosts = 0;
  std::size_t owned() const { return particles.size() - ghosts; }
  // The particle ids each [[particles]] source gave, [first, last) in the order of the
  // scenario (an inflow: from its first grain on); set by build_world.
  std::vector<std::pair<std::int64_t, std::int64_t>> source_ids;

  // The partners of wall contacts (Contact::j), "wall elements": an analytic wall is one, a
  // mesh one per triangle, and wall w's are [wall_elements[w], wall_elements[w + 1]). Empty
  // while no wall is a mesh: element j is wall j. Set from the walls by index_wall_elements.
  std::vector<std::uint32_t> wall_elements;
  void index_wall_elements() {
    wall_elements.clear();
    if (std::none_of(walls.begin(), walls.end(), [](const Wall& w) { return w.mesh != nullptr; })) return;
    wall_elements.push_back(0);
    for (const Wall& w : walls) wall_elements.push_back(wall_elements.back() + static_cast<std::uint32_t>(w.mesh ? w.mesh->size() : 1));
  }
  std::size_t element_count() const { return wall_elements.empty() ? walls.size() : wall_elements.back(); }
  std::uint32_t wall_of(std::uint32_t j) const {
    if (wall_elements.empty()) return j;
    return static_cast<std::uint32_t>(std::upper_bound(wall_elements.begin(), wall_elements.end(), j) - wall_elements.begin() - 1);
  }
  // Where a particle centred at x touches wall element j, at any distance: the wall's touch,
  // or the mesh triangle's; false when the triangle does not count the contact (world/mesh.hpp).
  bool touch_element(std::uint32_t j, const Vec3& x, WallTouch& out) const {
    const std::uint32_t w = wall_of(j);
    const Wall& wall = walls[w];
    if (!wall.mesh) {
      out = wall.touch(x);
      return true;
    }
    return touch_triangle(wall, j - wall_elements[w], wall.to_mesh(x), INFINITY, out);
  }
};

}  // namespace tsubu
