// Cone walls (docs/scenario.md, [[walls]] shape = "cone"): the face's distance and normal on
// both sides and the rims beyond its ends; a cone of equal radii is the cylinder, to the bit,
// along its length; a ball sliding or rolling down a hopper's face moves as down the plane
// that touches the face along the ball's path; a ball leaves through the outlet; the hopper
// example gives the same bits on 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scenario_run.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

// A hopper at 45 degrees: the outlet of radius 0.01 m about the origin, widening upwards to
// 0.05 m at z = 0.04 m.
Wall hopper(double radius = 0.01, double end_radius = 0.05, double length = 0.04, bool inside = true) {
  Wall w;
  w.shape = WallShape::cone;
  w.point = {0, 0, 0};
  w.axis = {0, 0, 1};
  w.radius = radius;
  w.end_radius = end_radius;
  w.length = length;
  w.inside = inside;
  return w;
}

TEST(ConeWall, TouchGivesTheFaceDistanceAlongItsNormalAndTheRimsBeyondItsEnds) {
  const Wall in = hopper(), out = hopper(0.01, 0.05, 0.04, false);
  const double h = std::sqrt(0.5);
  // Above the face: the face's radius at z = 0.02 is 0.03, the centre 0.02 in from it.
  const WallTouch a = in.touch({0, 0.01, 0.02});
  EXPECT_NEAR(a.distance, 0.02 * h, 1e-15);
  EXPECT_NEAR(a.normal.y, -h, 1e-15);  // towards the axis and up
  EXPECT_NEAR(a.normal.z, h, 1e-15);
  EXPECT_EQ(a.normal.x, 0);
  const WallTouch b = out.touch({0, 0.01, 0.02});  // the other side: behind the face
  EXPECT_NEAR(b.distance, -0.02 * h, 1e-15);
  EXPECT_NEAR(b.normal.z, -h, 1e-15);
  // Below the outlet, on the axis: the rim's circle, 0.01 across and 0.01 down.
  const WallTouch c = in.touch({0, 0, -0.01});
  EXPECT_NEAR(c.distance, 0.01 * std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(c.normal.z, -h, 1e-15);
  // Beyond the upper rim, outwards: the distance from the rim from any side.
  const WallTouch d = in.touch({0.08, 0, 0.08});
  EXPECT_NEAR(d.distance, 0.05, 1e-15);  // from (0.05, 0, 0.04): (0.03, 0, 0.04)
  EXPECT_NEAR(d.normal.x, 0.6, 1e-15);
  EXPECT_NEAR(d.normal.z, 0.8, 1e-15);
  // A turning cone's surface moves at omega rho about its axis at the nearest point.
  Wall turning = in;
  turning.angular_velocity = {0, 0, 3};
  const Vec3 v = turning.surface_velocity_at({0, 0.01, 0.02});  // nearest point at radius 0.02
  EXPECT_NEAR(norm(v), 3 * 0.02, 1e-15);
}

// Along its length a cone of equal radii is the cylinder of that radius: the same distance
// and normal, to the bit, on both sides.
TEST(ConeWall, ACylindricalConeIsTheCylinderToTheBit) {
  for (const bool inside : {true, false}) {
    Wall pipe = hopper(0.03, 0.03, 0.1, inside), cylinder = pipe;
    cylinder.shape = WallShape::cylinder;
    Random rng(3);
    for (int k = 0; k < 1000; ++k) {
      const Vec3 x{0.1 * rng.uniform() - 0.05, 0.1 * rng.uniform() - 0.05, 0.002 + 0.096 * rng.uniform()};
      const WallTouch a = pipe.touch(x), b = cylinder.touch(x);
      ASSERT_EQ(a.distance, b.distance) << k;
      ASSERT_EQ(a.normal, b.normal) << k;
    }
  }
}

// A ball released on the inside of a hopper's face, in the plane through the axis, slides
// (frictionless) or rolls (Mindlin, mu = 0.5) down the face's generatrix exactly as down the
// plane that touches the cone along that line: the same overlap along the same normal, so the
// same path to round-off, until it reaches the outlet.
TEST(ConeWall, ABallMovesDownAHopperFaceAsDownTheTangentPlane) {
  const double r = 0.003, dt = 1e-6, h = std::sqrt(0.5);
  const Vec3 n{-h, 0, h};  // the face's normal where y = 0, x > 0
  const Vec3 start = Vec3{0.04, 0, 0.03} + (r - 1e-7) * n;  // on the face at z = 0.03
  for (const char* tangential : {"none", "mindlin"}) {
    auto run = [&](const Wall& wall) {
      auto [world, model] =
          testing::make_world({"glass", 2500, 1e8, 0.3}, testing::spec_of("hertz_tsuji", tangential, 0.5), dt, {0, 0, -9.81});
      world.walls.push_back(wall);
      world.particles.add(0, 0, 2 * r, 2500, start, {});
      Simulation sim(std::move(world), std::move(model), Integrator::velocity_verlet, {});
      sim.start();
      sim.advance_to(50000);  // 0.05 s: about 7 mm down the face
      return sim.world().particles;
    };
    Wall plane;
    plane.point = {0.01, 0, 0};
    plane.normal = n;
    const Particles on_cone = run(hopper(0.01, 0.06, 0.05)), on_plane = run(plane);
    const double travelled = norm(on_plane.position[0] - start);
    std::printf("%s: %.6g m down the face; cone - plane %.3g m, speed %.3g m/s, spin %.3g rad/s\n", tangential, travelled,
                norm(on_cone.position[0] - on_plane.position[0]), norm(on_cone.velocity[0] - on_plane.velocity[0]),
                norm(on_cone.omega[0] - on_plane.omega[0]));
    EXPECT_GT(travelled, 0.005);
    EXPECT_LT(norm(on_cone.position[0] - on_plane.position[0]), 1e-15);
    EXPECT_LT(norm(on_cone.velocity[0] - on_plane.velocity[0]), 1e-13);
    EXPECT_LT(norm(on_cone.omega[0] - on_plane.omega[0]), 1e-10);
    EXPECT_EQ(on_cone.position[0].y, 0);  // it stays in the plane through the axis
  }
}

// A ball sliding down the face reaches the outlet and falls through it, away from the rim.
TEST(ConeWall, ABallLeavesThroughTheOutlet) {
  const double r = 0.003, dt = 1e-6, h = std::sqrt(0.5);
  auto [world, model] =
      testing::make_world({"glass", 2500, 1e8, 0.3}, testing::spec_of("hertz_tsuji", "none", 0.5), dt, {0, 0, -9.81});
  world.walls.push_back(hopper());
  world.particles.add(0, 0, 2 * r, 2500, Vec3{0.03, 0, 0.02} + r * Vec3{-h, 0, h}, {});
  Simulation sim(std::move(world), std::move(model), Integrator::velocity_verlet, {});
  sim.start();
  sim.advance_to(200000);  // 0.2 s
  const Particles& p = sim.world().particles;
  std::printf("after 0.2 s: z = %.4g m, %d contacts\n", p.position[0].z, p.contact_count[0]);
  EXPECT_LT(p.position[0].z, -0.02);
  EXPECT_EQ(p.contact_count[0], 0);
}

// The hopper of examples/hopper/hopper.toml, 0.05 s: 1 and 2 threads, the same bits.
TEST(ConeWall, TheHopperGivesTheSameBitsForOneAndTwoThreads) {
  const Scenario sc = testing::example_scenario("hopper/hopper.toml", {"simulation.duration=0.05", "search.sort_every=100"});
  EXPECT_TRUE(testing::same_particle_bits(testing::run_scenario(sc, 1), testing::run_scenario(sc, 2)));
}

// The same hopper filling in still water with hindered settling (the room the cone leaves
// each grain's ball: fluid/crowding.hpp, cone_cut_volume, its rate for block steps), with
// velocity Verlet and with block steps: 1 and 2 threads, the same bits.
TEST(ConeWall, TheHopperInWaterWithHinderedSettlingGivesTheSameBitsForOneAndTwoThreads) {
  for (const std::string integrator : {"velocity_verlet", "block_hermite"}) {
    std::vector<std::string> sets = {"simulation.duration=0.03", "search.sort_every=100", "fluid.density=1000",
                                     "fluid.kinematic_viscosity=1e-6", "fluid.drag=true", "fluid.hindered_settling=true",
                                     "simulation.integrator=\"" + integrator + "\""};
    if (integrator == "block_hermite") sets.push_back("simulation.dt=1e-3");
    const Scenario sc = testing::example_scenario("hopper/hopper.toml", sets);
    const World one = testing::run_scenario(sc, 1);
    EXPECT_GT(one.particles.size(), 50u) << integrator;
    EXPECT_TRUE(testing::same_particle_bits(one, testing::run_scenario(sc, 2))) << integrator;
  }
}

}  // namespace
}  // namespace tsubu
