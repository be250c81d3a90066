#include "tsubu/world/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "tsubu/world/domain.hpp"

namespace tsubu {

namespace {

// One side of an edge as a triangle has it: the edge's vertices p < q, the triangle, and
// which of its edges it is.
struct EdgeSide {
  std::uint32_t p, q, t, k;
};

// Lists of items per key as compressed rows: start[key] .. start[key + 1] index into items,
// filled in the order given (so each key's items stay in that order).
void rows(std::size_t keys, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& key_item,
          std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items) {
  start.assign(keys + 1, 0);
  for (const auto& [key, item] : key_item) ++start[key + 1];
  for (std::size_t k = 0; k < keys; ++k) start[k + 1] += start[k];
  items.resize(key_item.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& [key, item] : key_item) items[fill[key]++] = item;
}

}  // namespace

TriangleMesh::TriangleMesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  const std::size_t n = triangles_.size();
  normal_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& v = triangles_[t];
    for (std::uint32_t a : v)
      if (a >= vertices_.size())
        throw std::invalid_argument("triangle " + std::to_string(t) + " names vertex " + std::to_string(a) + " of " +
                                    std::to_string(vertices_.size()));
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
      throw std::invalid_argument("triangle " + std::to_string(t) + " repeats a vertex");
    const Vec3 c = cross(vertices_[v[1]] - vertices_[v[0]], vertices_[v[2]] - vertices_[v[0]]);
    const double area2 = norm(c);
    if (!(area2 > 0) || !std::isfinite(area2)) throw std::invalid_argument("triangle " + std::to_string(t) + " has no area");
    normal_[t] = c / area2;
  }
  box_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    box_[t] = {vertices_[triangles_[t][0]], vertices_[triangles_[t][0]]};
    for (int j = 1; j < 3; ++j)
      for (int a = 0; a < 3; ++a) {
        box_[t][0][a] = std::min(box_[t][0][a], vertices_[triangles_[t][j]][a]);
        box_[t][1][a] = std::max(box_[t][1][a], vertices_[triangles_[t][j]][a]);
      }
  }

  // Edges, numbered in the order of their vertices (p, q); each edge's triangles in their order.
  std::vector<EdgeSide> sides;
  sides.reserve(3 * n);
  for (std::uint32_t t = 0; t < n; ++t)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles_[t][k], b = triangles_[t][(k + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  std::sort(sides.begin(), sides.end(), [](const EdgeSide& a, const EdgeSide& b) {
    return a.p != b.p ? a.p < b.p : (a.q != b.q ? a.q < b.q : a.t < b.t);
  });
  edge_of_.resize(n);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_triangle;
  for (std::size_t s = 0; s < sides.size(); ++s) {
    if (s == 0 || sides[s].p != sides[s - 1].p || sides[s].q != sides[s - 1].q) edge_vertices_.push_back({sides[s].p, sides[s].q});
    const auto e = static_cast<std::uint32_t>(edge_vertices_.size() - 1);
    edge_of_[sides[s].t][sides[s].k] = e;
    edge_triangle.emplace_back(e, sides[s].t);
  }
  rows(edge_vertices_.size(), edge_triangle, edge_start_, edge_triangles_);

  // Each triangle's inward vectors across its edges; a coplanar pair shares one, negated.
  inward_.resize(n);
  for (std::uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto [p, q] = edge_vertices_[edge_of_[t][k]];
      const Vec3 third = vertices_[triangles_[t][(k + 2) % 3]];
      Vec3 w = cross(normal_[t], vertices_[q] - vertices_[p]);
      if (dot(third - vertices_[p], w) < 0) w = -w;
      inward_[t][k] = w;
    }
  const std::size_t m = edge_vertices_.size();
  edge_flat_.assign(m, 0);
  edge_bend_.assign(m, 0.0);
  for (std::uint32_t e = 0; e < m; ++e) {
    if (edge_start_[e + 1] - edge_start_[e] != 2) continue;
    const std::uint32_t owner = edge_triangles_[edge_start_[e]], other = edge_triangles_[edge_start_[e] + 1];
    const auto [p, q] = edge_vertices_[e];
    std::uint32_t far = 0;
    for (std::uint32_t a : triangles_[other])
      if (a != p && a != q) far = a;
    const Vec3 from_p = vertices_[far] - vertices_[p];
    edge_bend_[e] = dot(from_p, normal_[owner]);
    const int k_owner = edge_of_[owner][0] == e ? 0 : (edge_of_[owner][1] == e ? 1 : 2);
    const Vec3& w = inward_[owner][k_owner];
    // Coplanar: the normals agree to kFlatAngle (either way round) and the two triangles lie
    // on either side of the edge (not folded onto each other).
    const bool flat = norm(cross(normal_[owner], normal_[other])) < kFlatAngle && dot(from_p, w) < 0;
    if (!flat) continue;
    edge_flat_[e] = 1;
    const int k_other = edge_of_[other][0] == e ? 0 : (edge_of_[other][1] == e ? 1 : 2);
    inward_[other][k_other] = -w;
  }

  // Each vertex's triangles (in their order) and edges.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> vertex_triangle, vertex_edge;
  for (std::uint32_t t = 0; t < n; ++t)
    for (std::uint32_t a : triangles_[t]) vertex_triangle.emplace_back(a, t);
  for (std::uint32_t e = 0; e < m; ++e) vertex_edge.emplace_back(edge_vertices_[e][0], e), vertex_edge.emplace_back(edge_vertices_[e][1], e);
  rows(vertices_.size(), vertex_triangle, vertex_start_, vertex_triangles_);
  rows(vertices_.size(), vertex_edge, vertex_edge_start_, vertex_edges_);
}

NearestFeature TriangleMesh::nearest(std::uint32_t t, const Vec3& x) const {
  const auto& tri = triangles_[t];
  bool outside[3];
  for (int k = 0; k < 3; ++k) outside[k] = !(dot(x - vertices_[edge_vertices_[edge_of_[t][k]][0]], inward_[t][k]) > 0);
  if (!outside[0] && !outside[1] && !outside[2]) return {NearestFeature::face, t, x - dot(x - vertices_[tri[0]], normal_[t]) * normal_[t]};
  double along[3];  // the position of x's projection along each edge, from its vertex p (0) to q (1)
  for (int k = 0; k < 3; ++k) {
    const auto [p, q] = edge_vertices_[edge_of_[t][k]];
    const Vec3 d = vertices_[q] - vertices_[p];
    along[k] = dot(x - vertices_[p], d) / dot(d, d);
  }
  // An edge's region: outside across it, and its projection within it.
  NearestFeature best{NearestFeature::vertex, 0, {}};
  double best2 = INFINITY;
  for (int k = 0; k < 3; ++k) {
    if (!outside[k] || !(along[k] > 0 && along[k] < 1)) continue;
    const std::uint32_t e = edge_of_[t][k];
    const auto [p, q] = edge_vertices_[e];
    const Vec3 point = vertices_[p] + along[k] * (vertices_[q] - vertices_[p]);
    if (const double d2 = norm2(x - point); d2 < best2) best2 = d2, best = {NearestFeature::edge, e, point};
  }
  if (best.kind == NearestFeature::edge) return best;
  // A vertex's region: beyond it along both its edges.
  for (int j = 0; j < 3; ++j) {
    const std::uint32_t v = tri[j];
    bool beyond = true;
    for (int k : {j, (j + 2) % 3}) {
      const std::uint32_t p = edge_vertices_[edge_of_[t][k]][0];
      beyond = beyond && (v == p ? along[k] <= 0 : along[k] >= 1);
    }
    if (beyond) return {NearestFeature::vertex, v, vertices_[v]};
  }
  // Round-off between regions: the nearest vertex.
  for (std::uint32_t v : tri)
    if (const double d2 = norm2(x - vertices_[v]); d2 < best2) best2 = d2, best = {NearestFeature::vertex, v, vertices_[v]};
  return best;
}

bool TriangleMesh::may_reach(std::uint32_t t, const Vec3& x, double reach) const {
  return grown_box_holds(box_[t], x, reach) &&
         std::abs(dot(x - vertices_[triangles_[t][0]], normal_[t])) <= reach * (1 + kReachMargin);
}

bool TriangleMesh::concave_from(std::uint32_t e, const Vec3& x) const {
  if (edge_flat_[e] || edge_start_[e + 1] - edge_start_[e] != 2) return false;
  const std::uint32_t owner = edge_triangles_[edge_start_[e]];
  return dot(x - vertices_[edge_vertices_[e][0]], normal_[owner]) * edge_bend_[e] > 0;
}

bool TriangleMesh::vertex_concave_from(std::uint32_t v, const Vec3& x) const {
  bool any = false;
  for (std::uint32_t s = vertex_edge_start_[v]; s < vertex_edge_start_[v + 1]; ++s) {
    const std::uint32_t e = vertex_edges_[s];
    if (edge_flat_[e]) continue;
    if (!concave_from(e, x)) return false;
    any = true;
  }
  return any;
}

bool TriangleMesh::all_nearest(const std::vector<std::uint32_t>& start, const std::vector<std::uint32_t>& list,
                               std::uint32_t at, NearestFeature::Kind kind, std::uint32_t index, std::uint32_t asking,
                               const Vec3& x) const {
  for (std::uint32_t s = start[at]; s < start[at + 1]; ++s) {
    if (list[s] == asking) continue;  // its own nearest feature is the one asked about
    const NearestFeature f = nearest(list[s], x);
    if (f.kind != kind || f.index != index) return false;
  }
  return true;
}

bool TriangleMesh::touch(std::uint32_t t, const Vec3& x, double r, WallTouch& out, NearestFeature* feature,
                         bool* spare) const {
  if (spare) *spare = false;
  if (!may_reach(t, x, r)) return false;
  const NearestFeature f = nearest(t, x);
  if (f.kind == NearestFeature::face) {  // its distance, the plane's, may_reach found within reach
    const double d = dot(x - vertices_[triangles_[t][0]], normal_[t]);
    if (d == 0) return false;
    out = {std::abs(d), d > 0 ? normal_[t] : -normal_[t]};
    if (feature) *feature = f;
    return true;
  }
  const Vec3 from = x - f.point;
  const double d = norm(from);
  if (!(d > 0) || !(d <= r * (1 + kReachMargin))) return false;
  // An edge or vertex: counted by its owner where it is the surface's nearest point around
  // it; by each triangle where the surface is concave there (see the header).
  const bool owned =
      f.kind == NearestFeature::edge
          ? concave_from(f.index, x) || (edge_triangles_[edge_start_[f.index]] == t &&
                                         all_nearest(edge_start_, edge_triangles_, f.index, f.kind, f.index, t, x))
          : vertex_concave_from(f.index, x) || (vertex_triangles_[vertex_start_[f.index]] == t &&
                                                all_nearest(vertex_start_, vertex_triangles_, f.index, f.kind, f.index, t, x));
  // Where the surface is flat across the edge or around the vertex, the nearest point moves
  // with the centre as on a face and the normal stands still: a face's rates
  // (touch_triangle_with_rates). Not owned, such a feature over which the centre lies (its
  // touch the plane's, same_contact) is a spare with the plane's touch: the triangles of a
  // flat vertex may disagree on its region to round-off, so that none owns it.
  const bool is_flat = flat(f);
  if (!owned) {
    if (!is_flat || !spare) return false;
    const double h = dot(x - vertices_[triangles_[t][0]], normal_[t]);
    const WallTouch plane{std::abs(h), h > 0 ? normal_[t] : -normal_[t]};
    if (h == 0 || !same_contact(plane, {d, from / d})) return false;
    out = plane;
    if (feature) *feature = {NearestFeature::face, t, x - h * normal_[t]};
    *spare = true;
    return false;
  }
  out = {d, from / d};
  if (feature) *feature = is_flat ? NearestFeature{NearestFeature::face, t, f.point} : f;
  return true;
}

bool TriangleMesh::flat(const NearestFeature& f) const {
  if (f.kind == NearestFeature::edge) return edge_flat_[f.index];
  if (f.kind == NearestFeature::face) return true;
  for (std::uint32_t s = vertex_edge_start_[f.index]; s < vertex_edge_start_[f.index + 1]; ++s)
    if (!edge_flat_[vertex_edges_[s]]) return false;
  return true;
}

}  // namespace tsubu
