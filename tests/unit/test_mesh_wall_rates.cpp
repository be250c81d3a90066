// The rates of mesh contacts for block steps (docs/scenario.md, "Mesh walls"): the touch of a
// triangle on dual numbers has the exact rates of its distance and normal at a face, an edge
// and a vertex, of a still, moving or turning mesh; the surface's velocity under a grain has
// its rate, and so has the force. The runs with block steps are in test_mesh_walls.cpp
// (MeshWallBlockSteps.*).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "mesh_plate.hpp"
#include "tsubu/forces/evaluate.hpp"

namespace tsubu {
namespace {

using testing::mesh_wall;
using testing::pyramid;

// `wall` at the time s: moved by its velocity and turned by its angular velocity from where
// it is at 0.
Wall at_time(Wall wall, double s) {
  wall.point += s * wall.velocity;
  wall.turn_to(s);
  return wall;
}

// The triangle of `wall` that counts the touch of a centre at x (the only one at these
// points), its touch and nearest feature.
struct Counted {
  std::uint32_t triangle = 0;
  WallTouch touch;
  NearestFeature feature;
};
Counted counted(const Wall& wall, const Vec3& x) {
  Counted c;
  int found = 0;
  for (std::uint32_t t = 0; t < wall.mesh->size(); ++t) {
    WallTouch touch;
    NearestFeature f;
    if (touch_triangle(wall, t, wall.to_mesh(x), INFINITY, touch, &f)) c = {t, touch, f}, ++found;
  }
  EXPECT_EQ(found, 1);
  return c;
}

// The touch with rates of a centre at x moving at v against the central differences of the
// touch along the path, the wall moving and turning with it (to h^2: 1e-7 of the rates with
// h = 1e-6 s): distance, normal and the surface's velocity under the grain.
void expect_exact_rates(const Wall& wall, const Vec3& x, const Vec3& v, NearestFeature::Kind kind, const char* what) {
  const Counted now = counted(wall, x);
  ASSERT_EQ(now.feature.kind, kind) << what;
  const BasicWallTouch<Dual> t = touch_triangle_with_rates(wall, now.feature.kind, now.feature.index, now.touch, x, v);
  EXPECT_EQ(value(t.distance), now.touch.distance) << what;
  EXPECT_EQ(value(t.normal), now.touch.normal) << what;
  const double h = 1e-6;
  const Wall ahead_wall = at_time(wall, h), behind_wall = at_time(wall, -h);
  const Counted ahead = counted(ahead_wall, x + h * v), behind = counted(behind_wall, x - h * v);
  ASSERT_EQ(ahead.triangle, now.triangle) << what;
  ASSERT_EQ(behind.triangle, now.triangle) << what;
  const double distance_rate = (ahead.touch.distance - behind.touch.distance) / (2 * h);
  const Vec3 normal_rate = (ahead.touch.normal - behind.touch.normal) / (2 * h);
  const Motion<Dual> motion{x, DualVec3(v, {}), DualVec3()};
  const DualVec3 surface = surface_velocity<Dual>(wall, motion, now.touch, now.feature.kind, now.feature.index);
  const Vec3 surface_rate = (ahead_wall.surface_velocity_at(x + h * v, ahead.touch) -
                             behind_wall.surface_velocity_at(x - h * v, behind.touch)) / (2 * h);
  std::printf("%s: distance rate %.9g (difference %.9g), normal rate |%.6g| off by %.3g, surface's |%.6g| off by %.3g\n",
              what, t.distance.d, distance_rate, norm(rate(t.normal)), norm(rate(t.normal) - normal_rate),
              norm(rate(surface)), norm(rate(surface) - surface_rate));
  EXPECT_NEAR(t.distance.d, distance_rate, 1e-7 * norm(v)) << what;
  EXPECT_LT(norm(rate(t.normal) - normal_rate), 1e-6 * std::max(norm(normal_rate), 1.0)) << what;
  EXPECT_EQ(value(surface), wall.surface_velocity_at(x, now.touch)) << what;
  EXPECT_LT(norm(rate(surface) - surface_rate), 1e-6 * std::max(norm(surface_rate), 1.0)) << what;
}

TEST(MeshWallRates, TheTouchWithRatesIsExactAtFacesEdgesAndVertices) {
  const Vec3 v{0.3, -0.2, 0.5};
  const Wall still = mesh_wall(pyramid());
  Wall turning = still;  // moving and turning about an axis off its apex
  turning.velocity = {0.1, 0.05, -0.2};
  turning.axis_offset = {0.002, -0.001, 0};
  turning.turn_at(Vec3{1, -2, 5});
  for (const bool turns : {false, true}) {
    const Wall* w = turns ? &turning : &still;
    expect_exact_rates(*w, {0.004, 0.001, 0.001}, v, NearestFeature::face, turns ? "turning, face" : "still, face");
    expect_exact_rates(*w, {0.004, 0.0045, 0.001}, v, NearestFeature::edge, turns ? "turning, edge" : "still, edge");
    expect_exact_rates(*w, {0.0003, -0.0002, 0.003}, v, NearestFeature::vertex, turns ? "turning, apex" : "still, apex");
  }
  // Along these paths the normal does turn at an edge and a vertex, and on a turning face.
  const Counted edge = counted(still, {0.004, 0.0045, 0.001});
  EXPECT_GT(norm(rate(touch_triangle_with_rates(still, edge.feature.kind, edge.feature.index, edge.touch,
                                                {0.004, 0.0045, 0.001}, v).normal)),
            1.0);
}

// A conveyor of triangles (surface_velocity on a mesh, moving with `motion`): its surface's
// velocity under the grain lies in the contact's plane, and turns with it at an edge and a
// vertex.
TEST(MeshWallRates, AConveyorsSurfaceVelocityHasTheRateOfTheContactsPlane) {
  const Vec3 v{0.3, -0.2, 0.5};
  Wall belt = mesh_wall(pyramid());
  belt.velocity = {0.1, 0.05, -0.2};
  belt.surface_velocity = {0.05, -0.02, 0.03};
  expect_exact_rates(belt, {0.004, 0.001, 0.001}, v, NearestFeature::face, "conveyor, face");
  expect_exact_rates(belt, {0.004, 0.0045, 0.001}, v, NearestFeature::edge, "conveyor, edge");
  expect_exact_rates(belt, {0.0003, -0.0002, 0.003}, v, NearestFeature::vertex, "conveyor, apex");
  const Vec3 x{0.004, 0.0045, 0.001};
  const Counted edge = counted(belt, x);
  const Vec3 u = belt.surface_velocity_at(x, edge.touch) - belt.velocity;
  EXPECT_LT(std::abs(dot(u, edge.touch.normal)), 1e-15 * norm(u)) << "in the contact's plane";
  const DualVec3 s = surface_velocity<Dual>(belt, Motion<Dual>{x, DualVec3(v, {}), DualVec3()}, edge.touch, edge.feature.kind,
                                             edge.feature.index);
  EXPECT_GT(norm(rate(s)), 1.0) << "the plane turns under the grain at an edge";
}

// The force's rate of a grain touching a turning, moving mesh at an edge, as the block steps
// evaluate it (surface_velocity and touch_with_rates on Dual): the central difference of the
// force along the path, the mesh moving with it.
TEST(MeshWallRates, TheForcesRateAtATurningEdgeIsTheDifferenceAlongThePath) {
  const double r = 0.5e-3, m = 1.4e-6;
  Wall wall = mesh_wall(pyramid());
  wall.velocity = {0.01, 0, -0.02};
  wall.turn_at(Vec3{0, 0.5, 2});
  const HertzSediment normal{5e8, 0.2};
  const MindlinSlip tangential{0.5, 0.17, 0.9};
  const Vec3 v{0.03, -0.02, -0.05}, a{20, 10, -5}, w{1, 2, -3}, alpha{50, -30, 10};
  // Just inside the reach of the ridge between faces 0 and 1 (over the edge's region).
  const Vec3 ridge = Vec3{0.004, 0.004, -0.004 * std::tan(20 * M_PI / 180)};
  const double slope = 20 * M_PI / 180;  // out of the ridge between the two faces' normals
  const Vec3 out = Vec3{std::sin(slope), std::sin(slope), 2 * std::cos(slope)} / norm(Vec3{std::sin(slope), std::sin(slope), 2 * std::cos(slope)});
  const Vec3 x = ridge + (r - 0.45e-6) * out;
  const Vec3 spring = 1e-8 * Vec3{1, -1, 0} / std::sqrt(2.0);  // in the contact's plane
  auto force = [&](double s, double dt) {
    const Vec3 xs = x + s * v + 0.5 * s * s * a, vs = v + s * a, ws = w + s * alpha;
    const Wall moved = at_time(wall, s);
    const WallTouch touch = counted(moved, xs).touch;
    ContactGeometry g = wall_geometry<double>(r, m, touch.normal, touch.distance, vs - moved.surface_velocity_at(xs, touch), ws);
    g.dt = dt;
    ContactHistory h{spring, {0, 0}};
    return evaluate(normal, tangential, NoRolling{}, g, h);
  };
  const Counted now = counted(wall, x);
  ASSERT_EQ(now.feature.kind, NearestFeature::edge);
  const Motion<Dual> motion{x, DualVec3(v, a), DualVec3(w, alpha)};
  const DualVec3 v_rel = motion.v - surface_velocity<Dual>(wall, motion, now.touch, now.feature.kind, now.feature.index);
  const BasicWallTouch<Dual> moving = touch_with_rates<Dual>(wall, motion, now.touch, v_rel, now.feature.kind, now.feature.index);
  DualContactGeometry g = wall_geometry<Dual>(r, m, moving.normal, moving.distance, v_rel, motion.w);
  ContactHistory h{spring, {0, 0}};
  const ContactForceRate exact = evaluate_with_rates(normal, tangential, NoRolling{}, g, h);
  const double step = 1e-9;
  const Vec3 fd = (force(step, step).total - force(-step, -step).total) / (2 * step);
  std::printf("overlap %.3g m, force rate |%.6g| N/s, off the difference by %.3g\n", value(g.delta), norm(rate(exact.total)),
              norm(fd - rate(exact.total)));
  EXPECT_GT(value(g.delta), 0);
  EXPECT_LT(norm(fd - rate(exact.total)), 1e-6 * norm(rate(exact.total)));
}

}  // namespace
}  // namespace tsubu
