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
// `feature` and `spare`, where given, as TriangleMesh::touch sets them (a spare's touch given too).
inline bool touch_triangle(const Wall& wall, std::uint32_t t, const Vec3& x, double r, WallTouch& out,
                           NearestFeature* feature = nullptr, bool* spare = nullptr) {
  const bool counts = wall.mesh->touch(t, x, r, out, feature, spare);
  if (counts || (spare && *spare)) out.normal = wall.from_mesh(out.normal);
  return counts;
}

// The same touch t of a particle centred at x moving at v (the box's frame) with its rates,
// its nearest feature `kind` (an edge: `edge`, the mesh's edge index) found at x. Relative to
// the mesh, which moves at wall.velocity and turns at wall.angular_velocity about
// point + axis_offset, the centre moves at u = v - velocity - omega x (x - axis point). The
// distance from the nearest point p changes at u.n (p moves across n, if at all), and the
// normal, n = (x - p)/d, at (I - n n)(u - p')/d, p' the nearest point's velocity along the
// feature: on a face p follows the centre in the plane (the normal stands still), on an edge
// it slides with u's part along the edge, at a vertex it stays; the mesh turning turns the
// normal besides, at omega x n. Exact: docs/scenario.md, "Mesh walls".
inline BasicWallTouch<Dual> touch_triangle_with_rates(const Wall& wall, NearestFeature::Kind kind, std::uint32_t edge,
                                                      const WallTouch& t, const Vec3& x, const Vec3& v) {
  const Vec3& omega = wall.angular_velocity;
  const Vec3& n = t.normal;
  const Vec3 u = v - wall.velocity - cross(omega, x - (wall.point + wall.axis_offset));
  const double approach = dot(u, n);
  Vec3 turn;  // the normal's rate relative to the mesh
  if (kind == NearestFeature::edge) {
    const Vec3 e = wall.from_mesh(wall.mesh->edge_direction(edge));
    turn = (u - dot(u, e) * e - approach * n) / t.distance;
  } else if (kind == NearestFeature::vertex) {
    turn = (u - approach * n) / t.distance;
  }
  return {Dual(t.distance, approach), DualVec3(n, turn + cross(omega, n))};
}

// How far a turning mesh's farthest vertex is from the axis it turns about, m (0 for a wall
// that does not turn so): the fastest its surface moves is that times its angular velocity.
inline double turning_reach(const Wall& wall) {
  const Vec3& k = wall.turn_axis;
  double reach = 0;
  if (!wall.mesh || k == Vec3{}) return reach;
  for (const Vec3& v : wall.mesh->vertices()) {
    const Vec3 off = v - wall.axis_offset;
    reach = std::max(reach, norm(off - dot(off, k) * k));
  }
  return reach;
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
  // or the mesh triangle's; false when the triangle does not count the contact and is no
  // spare for it (world/mesh.hpp).
  bool touch_element(std::uint32_t j, const Vec3& x, WallTouch& out) const {
    const std::uint32_t w = wall_of(j);
    const Wall& wall = walls[w];
    if (!wall.mesh) {
      out = wall.touch(x);
      return true;
    }
    bool spare = false;  // a contact may be a spare's (ForceField::touch_wall)
    return touch_triangle(wall, j - wall_elements[w], wall.to_mesh(x), INFINITY, out, nullptr, &spare) || spare;
  }
};

}  // namespace tsubu
