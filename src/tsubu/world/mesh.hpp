// Triangle-mesh walls: the geometry of a mesh and the contact of a ball with it
// (docs/scenario.md, "Mesh walls").
//
// A ball touches a triangle where the triangle's nearest point to its centre is: inside the
// face, on an edge or at a vertex. The triangles of a mesh share their edges and vertices,
// and a ball over a shared edge or vertex is as near to every triangle that has it: counted
// by each, it would feel the edge two or six times. So a contact at an edge or a vertex is
// counted once, by the one triangle that owns it (the one of lowest index), and only where
// the edge or vertex is the nearest point of the surface around it (a local minimum of the
// distance): every triangle that has it finds it nearest. On a flat mesh, then, a ball feels
// exactly one contact wherever it is, at the distance and along the normal of the plane (to
// round-off), and over a convex edge or corner one contact with the edge or corner.
//
// Where the surface is concave seen from the ball (a valley, a bowl), a ball touches both
// sides: each triangle's contact counts on its own, its edge and vertex contacts included,
// so that a contact slides from a face onto the valley's edge without a jump in force. A mesh
// that approximates a smooth concave surface (a drum of facets) touches a ball twice near its
// edges, as a faceted surface does; the analytic cylinder and cone are smooth.
//
// Where two triangles are coplanar (to kFlatAngle), the test that decides on which side of
// their shared edge a ball's centre is belongs to the edge, not to either triangle: one
// number, with the sign of one for the other, so that a centre over the edge is in exactly
// one face's region or on the edge, never in both or neither. The position along an edge is
// measured once per edge too (from its lower vertex index), so that the triangles that share
// it agree on whether a centre is beyond its end.
//
// Within round-off of a vertex of a flat mesh those tests, one per edge, need not meet in one
// point: a centre there can be inside two faces, and two contacts of a ball with a mesh at the
// same point (same_contact) are one, the later dropped; or the vertex's triangles can disagree
// on its region so that none counts it, and a triangle that finds the flat vertex or a flat
// edge nearest is then a spare that counts the plane's touch (TriangleMesh::touch,
// ForceField::touch_wall). Without it, a ball falling straight onto such a vertex of a tilted
// mesh was not seen until it was 80 um deep (block steps: validation/mesh_walls.py).
//
// The triangles are two-sided: a ball may touch either face. A centre in the surface itself
// has no normal and feels no contact.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tsubu/core/vec3.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

// What part of a triangle is nearest to a point: its face, one of its edges (the mesh's
// edge index) or one of its vertices (the mesh's vertex index); `point` is the nearest point.
struct NearestFeature {
  enum Kind : std::uint8_t { face, edge, vertex } kind = face;
  std::uint32_t index = 0;  // face: the triangle; edge: the edge; vertex: the vertex
  Vec3 point;
};

// Whether two contacts of a ball with a mesh are the same, to round-off: the same normal and
// distance (a valley's two faces, a box's corner, differ by their angle).
inline bool same_contact(const WallTouch& a, const WallTouch& b) {
  return norm2(a.normal - b.normal) < 1e-18 && std::abs(a.distance - b.distance) <= 1e-9 * a.distance;
}

class TriangleMesh {
 public:
  // Two triangles whose normals differ by less than this are coplanar, rad.
  static constexpr double kFlatAngle = 1e-9;
  // The tests of reach (may_reach, touch) give up on a triangle only when it is farther than
  // the reach by more than this part of it: the nearest point's round-off, some units in the
  // last place of the coordinates, lies far within that margin, so that such a triangle is
  // surely out of reach.
  static constexpr double kReachMargin = 1e-6;

  // Throws std::invalid_argument for a triangle with a repeated vertex or no area, or an
  // index out of range.
  TriangleMesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles);

  std::size_t size() const { return triangles_.size(); }
  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::array<std::uint32_t, 3>& triangle(std::size_t t) const { return triangles_[t]; }
  const Vec3& normal(std::size_t t) const { return normal_[t]; }  // unit, by the right-hand rule
  std::size_t edges() const { return edge_vertices_.size(); }

  // The nearest part of triangle t to x.
  NearestFeature nearest(std::uint32_t t, const Vec3& x) const;
  // Whether x may be within `reach` of triangle t: false where it surely is not (kReachMargin),
  // being farther than that from t's plane or, along some axis, from t's bounding box (each a
  // lower bound of its distance from the triangle: grown_box_holds). A cheap test before
  // nearest().
  bool may_reach(std::uint32_t t, const Vec3& x, double reach) const;
  // Whether triangle t counts the contact of a ball of radius r centred at x (see above), and
  // if so where it touches: the distance of x from the nearest point and the unit normal from
  // there to x. False for a triangle surely out of the ball's reach (kReachMargin), which is
  // not asked about further (r = INFINITY: none is). `feature`, where given, gets the nearest
  // feature of a contact that counts (for the touch's rates: touch_triangle_with_rates), a face
  // where the surface is flat there (an edge between coplanar triangles, a vertex inside them;
  // counted only with the centre over it, its touch the plane's to round-off). `spare`, where
  // given, is set for a flat edge or vertex
  // that t has and does not own: its touch (the plane's) and feature are given, and it counts
  // where no contact of the mesh at the same point does (ForceField::touch_wall).
  bool touch(std::uint32_t t, const Vec3& x, double r, WallTouch& out, NearestFeature* feature = nullptr,
             bool* spare = nullptr) const;
  // Edge e's unit direction, from its lower vertex index to its higher.
  Vec3 edge_direction(std::uint32_t e) const {
    const Vec3 d = vertices_[edge_vertices_[e][1]] - vertices_[edge_vertices_[e][0]];
    return d / norm(d);
  }

  // Whether triangles a and b share a vertex.
  bool adjacent(std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t u : triangles_[a])
      for (std::uint32_t v : triangles_[b])
        if (u == v) return true;
    return false;
  }
  // Triangle t's bounding box: its lower and upper corners.
  const std::array<Vec3, 2>& box(std::size_t t) const { return box_[t]; }

 private:
  // Whether the surface is flat at the feature: a face; an edge between two coplanar
  // triangles; a vertex all of whose edges are such (not on the mesh's rim).
  bool flat(const NearestFeature& f) const;
  // Per edge (its vertices p < q): the triangles that share it, the coplanar flag, and the
  // bend of its second triangle out of its owner's plane (for concavity).
  bool concave_from(std::uint32_t e, const Vec3& x) const;
  bool vertex_concave_from(std::uint32_t v, const Vec3& x) const;
  // Whether the feature (kind, index) is the nearest to x of every triangle of list[start[at]
  // .. start[at + 1]) (an edge's or a vertex's), `asking` (one of them) known to find it so.
  bool all_nearest(const std::vector<std::uint32_t>& start, const std::vector<std::uint32_t>& list, std::uint32_t at,
                   NearestFeature::Kind kind, std::uint32_t index, std::uint32_t asking, const Vec3& x) const;

  std::vector<Vec3> vertices_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<Vec3> normal_;
  std::vector<std::array<Vec3, 2>> box_;  // per triangle, its bounding box's lower and upper corners
  // Triangle t's edge k runs between its vertices k and k+1 (mod 3): edge_of_[t][k] is its
  // index, inward_[t][k] a vector in t's plane, across the edge, towards t's inside.
  std::vector<std::array<std::uint32_t, 3>> edge_of_;
  std::vector<std::array<Vec3, 3>> inward_;
  std::vector<std::array<std::uint32_t, 2>> edge_vertices_;  // p < q
  std::vector<std::uint32_t> edge_start_, edge_triangles_;    // the triangles of edge e, lowest first
  std::vector<std::uint8_t> edge_flat_;
  std::vector<double> edge_bend_;  // the second triangle's far vertex above its owner's plane, m
  std::vector<std::uint32_t> vertex_start_, vertex_triangles_;  // the triangles of vertex v, lowest first
  std::vector<std::uint32_t> vertex_edge_start_, vertex_edges_;  // the edges of vertex v
};

// Whether the box {lower, upper} grown by `reach` on every side, and by kReachMargin of it,
// holds x: where it does not, x is surely farther than the reach from all in the box.
inline bool grown_box_holds(const std::array<Vec3, 2>& box, const Vec3& x, double reach) {
  const double grown = reach * (1 + TriangleMesh::kReachMargin);
  return x.x >= box[0].x - grown && x.x <= box[1].x + grown && x.y >= box[0].y - grown && x.y <= box[1].y + grown &&
         x.z >= box[0].z - grown && x.z <= box[1].z + grown;
}

}  // namespace tsubu
