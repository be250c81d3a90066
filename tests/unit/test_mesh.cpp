// Triangle-mesh geometry (world/mesh.hpp): a ball over a flat mesh touches exactly one
// triangle wherever it is, at the plane's distance and normal, over faces, edges and
// vertices alike; over a convex ridge or corner it touches the edge or corner once; in a
// valley it touches both sides; inside a box's corner its three faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "mesh_plate.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/mesh.hpp"

namespace tsubu {
namespace {

using testing::plate;

struct Touches {
  int count = 0;
  WallTouch touch;  // the last one found
};

// The contacts a ball of radius 0.01 centred at x has with the mesh, one of each
// same_contact set.
Touches touches(const TriangleMesh& mesh, const Vec3& x) {
  Touches out;
  std::vector<WallTouch> found;
  for (std::uint32_t t = 0; t < mesh.size(); ++t) {
    WallTouch w;
    if (!mesh.touch(t, x, 0.01, w) || !(w.distance < 0.01)) continue;
    if (std::none_of(found.begin(), found.end(), [&](const WallTouch& f) { return same_contact(f, w); }))
      found.push_back(w), ++out.count, out.touch = w;
  }
  return out;
}

// A rotation taking z to the unit vector n (about the axis z x n).
Vec3 rotate(const Vec3& a, const Vec3& n) {
  const Vec3 z{0, 0, 1}, k = cross(z, n);
  const double s = norm(k), c = dot(z, n);
  if (s == 0) return a;
  const Vec3 u = k / s;
  return c * a + s * cross(u, a) + (1 - c) * dot(u, a) * u;
}

TEST(MeshGeometry, AFlatMeshTouchesOnceAtThePlanesDistanceEverywhere) {
  const Vec3 n = Vec3{0.3, -0.2, 0.9} / norm(Vec3{0.3, -0.2, 0.9});
  const Vec3 origin{0.1, 0.2, -0.05};
  const double h = 0.01;
  const TriangleMesh mesh = plate(6, h, [&](const Vec3& a) { return origin + rotate(a, n); });
  const Vec3 e1 = rotate({1, 0, 0}, n), e2 = rotate({0, 1, 0}, n);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> across(0.5 * h, 5.5 * h), up(1e-4, 4e-3);
  auto check = [&](double a, double b, double d) {
    const Vec3 x = origin + a * e1 + b * e2 + d * n;
    const Touches t = touches(mesh, x);
    ASSERT_EQ(t.count, 1) << "at " << a / h << ", " << b / h;
    const double plane = dot(x - origin, n);
    EXPECT_NEAR(t.touch.distance, plane, 4e-17) << a / h << ", " << b / h;
    EXPECT_NEAR(norm(t.touch.normal - n), 0, 1e-13) << a / h << ", " << b / h;
    // From below: the same, with the normal turned.
    const Touches below = touches(mesh, origin + a * e1 + b * e2 - d * n);
    ASSERT_EQ(below.count, 1);
    EXPECT_NEAR(norm(below.touch.normal + n), 0, 1e-13);
  };
  for (int s = 0; s < 3000; ++s) check(across(rng), across(rng), up(rng));
  // Over every vertex, over the middle of every edge, and along the diagonals.
  for (int j = 1; j < 6; ++j)
    for (int i = 1; i < 6; ++i) {
      check(i * h, j * h, 2e-3);
      check((i + 0.5) * h, j * h, 2e-3);
      check(i * h, (j + 0.5) * h, 2e-3);
      check((i + 0.5) * h, (j + 0.5) * h, 2e-3);
    }
}

TEST(MeshGeometry, AnAxisAlignedFlatMeshGivesThePlanesBitsOverItsFaces) {
  const TriangleMesh mesh = plate(4, 0.01, [](const Vec3& a) { return a; });
  const Wall floor = [] {
    Wall w;
    w.normal = {0, 0, 1};
    return w;
  }();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> across(0.001, 0.039), up(1e-4, 4e-3);
  for (int s = 0; s < 1000; ++s) {
    const Vec3 x{across(rng), across(rng), up(rng)};
    const Touches t = touches(mesh, x);
    ASSERT_EQ(t.count, 1);
    const WallTouch plane = floor.touch(x);
    EXPECT_EQ(t.touch.distance, plane.distance);
    EXPECT_EQ(t.touch.normal, plane.normal);
  }
}

// A roof: two faces meeting at a ridge along y at x = 0, z = 0, sloping down at 30 degrees.
TriangleMesh roof(double slope_degrees, double sign = -1) {
  const double s = std::tan(slope_degrees * M_PI / 180) * sign;
  std::vector<Vec3> v{{0, 0, 0}, {0, 1, 0}, {1, 0, s}, {1, 1, s}, {-1, 0, s}, {-1, 1, s}};
  return TriangleMesh(v, {{{0, 2, 3}}, {{0, 3, 1}}, {{0, 1, 5}}, {{0, 5, 4}}});
}

TEST(MeshGeometry, AConvexRidgeTouchesOnceAtTheEdgeAndValleysTouchBothSides) {
  const TriangleMesh ridge = roof(30);
  // Straight above the ridge: the edge, once.
  Touches t = touches(ridge, {0, 0.4, 0.002});
  ASSERT_EQ(t.count, 1);
  EXPECT_DOUBLE_EQ(t.touch.distance, 0.002);
  EXPECT_DOUBLE_EQ(t.touch.normal.z, 1);
  // Just off the ridge, within its wedge (the normals at +-30 degrees): still the edge.
  t = touches(ridge, {0.0005, 0.4, 0.002});
  ASSERT_EQ(t.count, 1);
  EXPECT_NEAR(t.touch.distance, std::hypot(0.0005, 0.002), 1e-15);
  // Over one face: that face alone.
  t = touches(ridge, {0.01, 0.4, 0.0});
  ASSERT_EQ(t.count, 1);
  EXPECT_NEAR(t.touch.normal.z, std::cos(M_PI / 6), 1e-15);
  // The same mesh seen from below is a valley: over both faces it touches both.
  t = touches(ridge, {0.0005, 0.4, -0.002});
  EXPECT_EQ(t.count, 2);
  const TriangleMesh valley = roof(30, +1);
  EXPECT_EQ(touches(valley, {0.0005, 0.4, 0.002}).count, 2);
  // In a valley beyond one face's edge, the far face's edge contact is its own: a ball over
  // the left face near the valley touches the left face and the right face's edge.
  EXPECT_EQ(touches(valley, {-0.0015, 0.4, 0.002}).count, 2);
}

// The unit cube's surface, 12 triangles.
TriangleMesh cube() {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k) v.push_back({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  return TriangleMesh(v, {{{0, 2, 3}}, {{0, 3, 1}}, {{4, 5, 7}}, {{4, 7, 6}}, {{0, 1, 5}}, {{0, 5, 4}},
                          {{2, 6, 7}}, {{2, 7, 3}}, {{0, 4, 6}}, {{0, 6, 2}}, {{1, 3, 7}}, {{1, 7, 5}}});
}

TEST(MeshGeometry, ACubeTouchesOnceOutsideItsCornersAndThriceInsideThem) {
  const TriangleMesh box = cube();
  // Outside, beyond the corner (1, 1, 1): the corner once.
  Touches t = touches(box, {1.001, 1.002, 1.003});
  ASSERT_EQ(t.count, 1);
  EXPECT_NEAR(t.touch.distance, std::sqrt(1e-6 + 4e-6 + 9e-6), 1e-15);
  // Outside, beyond an edge: the edge once; over a face across its diagonal: the face once.
  EXPECT_EQ(touches(box, {1.001, 0.5, 1.002}).count, 1);
  EXPECT_EQ(touches(box, {0.5, 0.5, 1.002}).count, 1);
  EXPECT_EQ(touches(box, {0.3, 0.3, 1.002}).count, 1);
  // Inside, near the corner: its three faces.
  t = touches(box, {0.999, 0.998, 0.997});
  EXPECT_EQ(t.count, 3);
}

// The tests of reach (may_reach, and touch's radius) leave out only triangles out of reach:
// a ball's contacts within its radius are those it has at any reach, to the bit.
TEST(MeshGeometry, TheTestsOfReachLeaveOutOnlyTrianglesOutOfReach) {
  const Vec3 n = Vec3{0.3, -0.2, 0.9} / norm(Vec3{0.3, -0.2, 0.9});
  const TriangleMesh meshes[] = {cube(), roof(30), roof(30, +1),
                                 testing::plate(4, 0.25, [&](const Vec3& a) { return rotate(a, n); })};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> around(-0.3, 1.3), radius(0.01, 0.4);
  int within = 0, without = 0;
  for (const TriangleMesh& mesh : meshes)
    for (int s = 0; s < 2000; ++s) {
      const Vec3 x{around(rng), around(rng), around(rng)};
      const double r = radius(rng);
      for (std::uint32_t t = 0; t < mesh.size(); ++t) {
        if (norm(x - mesh.nearest(t, x).point) < r) ASSERT_TRUE(mesh.may_reach(t, x, r));
        WallTouch any, near;
        const bool counts = mesh.touch(t, x, INFINITY, any), counts_near = mesh.touch(t, x, r, near);
        if (counts_near) ASSERT_TRUE(counts);
        if (!counts || !(any.distance < r)) {
          ++without;
          continue;
        }
        ++within;
        ASSERT_TRUE(counts_near);
        EXPECT_EQ(near.distance, any.distance);
        EXPECT_EQ(near.normal, any.normal);
      }
    }
  EXPECT_GT(within, 1000);
  EXPECT_GT(without, 1000);
}

TEST(MeshGeometry, RefusesTrianglesWithoutArea) {
  EXPECT_THROW(TriangleMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{{0, 1, 2}}}), std::invalid_argument);
  EXPECT_THROW(TriangleMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{{0, 1, 1}}}), std::invalid_argument);
  EXPECT_THROW(TriangleMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{{0, 1, 3}}}), std::invalid_argument);
}

}  // namespace
}  // namespace tsubu
