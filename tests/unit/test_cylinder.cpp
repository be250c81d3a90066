// Cylinder walls (docs/scenario.md, [[walls]] shape = "cylinder"): the nearest point and the
// normal inside and outside; a frictionless bead sliding inside a horizontal cylinder swings
// as a pendulum of length R - r, with its period and without losing energy; a ball resting on
// a horizontal bar presses into it as into a plane; a turning drum's surface moves at omega R
// along its circle; the drum example gives the same bits on 1 and 2 threads. A plane with a
// hole (an outlet): the rim's distance and normal, and a frictionless ball sliding off the
// rim where cos theta = 2/3. The pendulum and the rim with block steps too.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scenario_run.hpp"
#include "tsubu/forces/evaluate.hpp"
#include "tsubu/sim/simulation.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

Wall cylinder(double radius, bool inside) {
  Wall w;
  w.shape = WallShape::cylinder;
  w.point = {0, 0, 0};
  w.axis = {0, 1, 0};
  w.radius = radius;
  w.inside = inside;
  return w;
}

TEST(CylinderWall, TouchGivesTheDistanceAlongTheRadiusAndTheNormalTowardsTheParticles) {
  const Wall in = cylinder(0.1, true), out = cylinder(0.1, false);
  const Vec3 x{0.03, 7.0, -0.04};  // 0.05 from the axis, whatever its place along it
  const WallTouch a = in.touch(x), b = out.touch(x);
  EXPECT_NEAR(a.distance, 0.05, 1e-15);
  EXPECT_NEAR(a.normal.x, -0.6, 1e-15);
  EXPECT_NEAR(a.normal.z, 0.8, 1e-15);
  EXPECT_EQ(a.normal.y, 0);
  EXPECT_NEAR(b.distance, -0.05, 1e-15);  // the far side of an outside cylinder: inside the bar
  EXPECT_NEAR(b.normal.x, 0.6, 1e-15);
  // A turning drum: its surface at the nearest point moves at omega R along the circle.
  Wall drum = in;
  drum.angular_velocity = {0, 2, 0};
  const Vec3 v = drum.surface_velocity_at(x);
  EXPECT_NEAR(norm(v), 2 * 0.1, 1e-15);
  EXPECT_NEAR(dot(v, a.normal), 0, 1e-15);
}

// A bead of radius r released at rest 10 degrees up the inside of a horizontal cylinder of
// radius R, frictionless and without damping, slides as a pendulum of length L = R - r (to
// the overlap, 1e-5 of L): period 2 pi sqrt(L/g) (1 + theta0^2/16 + 11 theta0^4/3072), and
// it swings back to its starting height. Velocity Verlet at dt = 10 us, and block steps at
// dt = 0.5 ms (the contact's normal turns with the bead all the way: its rate enters the
// Hermite steps); sampled every dt, the highest sample is within (omega dt)^2/2 = 1.2e-5 of
// the top.
void swings_as_a_pendulum(Integrator integrator, double dt) {
  const double R = 0.1, r = 0.005, g = 9.81, theta0 = 10 * M_PI / 180;
  auto [world, model] = testing::make_world({"glass", 2500, 1e9, 0.3}, testing::spec_of("hertz_tsuji", "none", 1.0), dt,
                                            {0, 0, -g});
  world.walls.push_back(cylinder(R, true));
  const double L = R - r;
  world.particles.add(0, 0, 2 * r, 2500, {L * std::sin(theta0), 0, -L * std::cos(theta0)}, {});
  Simulation sim(std::move(world), std::move(model), integrator, {});
  sim.start();
  const double period = 2 * M_PI * std::sqrt(L / g) * (1 + theta0 * theta0 / 16 + 11 * std::pow(theta0, 4) / 3072);
  std::vector<double> crossings;  // times x changes sign
  double x_before = sim.world().particles.position[0].x, highest_after_one = 0;
  while (sim.world().time < 1.25 * period) {
    sim.step();
    const double x = sim.world().particles.position[0].x, t = sim.world().time;
    if ((x < 0) != (x_before < 0)) crossings.push_back(t - dt * x / (x - x_before));
    if (t > 0.75 * period) highest_after_one = std::max(highest_after_one, x);
    x_before = x;
  }
  ASSERT_GE(crossings.size(), 2u);
  const double measured = 2 * (crossings[1] - crossings[0]);
  std::printf("period %.7f s, pendulum %.7f s; amplitude after one swing %.7f of the first; %llu evaluations\n", measured,
              period, highest_after_one / (L * std::sin(theta0)),
              static_cast<unsigned long long>(sim.particle_force_evaluations()));
  EXPECT_NEAR(measured / period, 1.0, 2e-5);  // the overlap shortens L by 1e-5
  EXPECT_NEAR(highest_after_one / (L * std::sin(theta0)), 1.0, 1e-4);
}

TEST(CylinderWall, AFrictionlessBeadInsideACylinderSwingsAsAPendulum) {
  swings_as_a_pendulum(Integrator::velocity_verlet, 1e-5);
}
TEST(CurvedWallBlockSteps, AFrictionlessBeadInsideACylinderSwingsAsAPendulum) {
  swings_as_a_pendulum(Integrator::block_hermite, 5e-4);
}

// A ball at the top of a horizontal bar (a cylinder with the particles outside) settles at
// the overlap it settles at on a horizontal plane through the bar's top: the same force
// along the same normal.
TEST(CylinderWall, ABallRestingOnABarPressesIntoItAsIntoAPlane) {
  const double R = 0.02, r = 0.004, dt = 1e-6;
  auto rest = [&](const Wall& wall) {
    auto [world, model] = testing::make_world({"glass", 2500, 1e7, 0.3}, testing::spec_of("hertz_tsuji", "none", 0.3), dt,
                                              {0, 0, -9.81});
    world.walls.push_back(wall);
    world.particles.add(0, 0, 2 * r, 2500, {0, 0, R + r}, {});
    Simulation sim(std::move(world), std::move(model), Integrator::velocity_verlet, {});
    sim.start();
    sim.advance_to(100000);
    return R + r - sim.world().particles.position[0].z;  // the overlap
  };
  Wall plane;
  plane.point = {0, 0, R};
  plane.normal = {0, 0, 1};
  const double on_bar = rest(cylinder(R, false)), on_plane = rest(plane);
  std::printf("overlap on the bar %.9g m, on the plane %.9g m\n", on_bar, on_plane);
  EXPECT_GT(on_plane, 0);
  EXPECT_NEAR(on_bar / on_plane, 1.0, 1e-9);
}

// The rotating drum of examples/drum/drum.toml, 0.05 s: 1 and 2 threads, the same bits.
TEST(CylinderWall, TheDrumGivesTheSameBitsForOneAndTwoThreads) {
  const Scenario sc = testing::example_scenario("drum/drum.toml", {"simulation.duration=0.05", "search.sort_every=100"});
  EXPECT_TRUE(testing::same_particle_bits(testing::run_scenario(sc, 1), testing::run_scenario(sc, 2)));
}

// A plate with a hole (a plane's hole_radius, an outlet): over the hole the nearest point is
// on the rim, elsewhere the plane's; the two meet at the rim's edge.
TEST(HoleInAPlane, OverTheHoleAGrainTouchesTheRim) {
  Wall plate;
  plate.point = {0, 0, 0};
  plate.normal = {0, 0, 1};
  plate.hole_radius = 0.01;
  const WallTouch face = plate.touch({0.02, 0, 0.003}), rim = plate.touch({0.007, 0, 0.004});
  EXPECT_EQ(face.distance, 0.003);
  EXPECT_EQ(face.normal, (Vec3{0, 0, 1}));
  EXPECT_NEAR(rim.distance, 0.005, 1e-15);  // from (0.01, 0, 0): (-0.003, 0, 0.004)
  EXPECT_NEAR(rim.normal.x, -0.6, 1e-15);
  EXPECT_NEAR(rim.normal.z, 0.8, 1e-15);
  const WallTouch edge = plate.touch({0.01 - 1e-12, 0, 0.002});
  EXPECT_NEAR(edge.distance, 0.002, 1e-15);
  EXPECT_NEAR(edge.normal.z, 1.0, 1e-15);
}

// A frictionless ball set on the rim of a hole, its centre straight above the edge (nudged
// 1e-6 m towards the hole) at its resting overlap, rolls over the edge as a bead slides off
// the top of a circle: its centre moves on the circle of radius r about the edge point and
// leaves it where cos(theta) = 2/3 (theta from the vertical: 48.19 degrees), then falls
// through. The normal dashpot keeps the contact's own vibration from parting it earlier; it
// does no work on the slide, where the overlap barely changes. A stiff contact (E = 1e11
// Pa): a Hertz contact softens as its force vanishes, its overlap lags behind the falling
// force and it parts later than a rigid edge would (e = 0.99: at 48.48 degrees for E = 1e9
// Pa, 48.27 for 1e11); the dashpot delays it a little more (e = 0.6: 48.36). 3e-3 in cos
// theta is 0.26 degrees.
// With velocity Verlet at dt = 1 us, and with block steps at dt = 10 us (the normal from the
// rim turns through 48 degrees under the ball).
void slides_off_the_rim(Integrator integrator, double dt) {
  const double a = 0.01, r = 0.002;
  auto [world, model] = testing::make_world({"glass", 2500, 1e11, 0.3}, testing::spec_of("hertz_tsuji", "none", 0.9), dt,
                                            {0, 0, -9.81});
  Wall plate;
  plate.point = {0, 0, 0};
  plate.normal = {0, 0, 1};
  plate.hole_radius = a;
  world.walls.push_back(plate);
  world.particles.add(0, 0, 2 * r, 2500, {a - 1e-6, 0, r - 4e-9}, {});  // resting on the edge
  Simulation sim(std::move(world), std::move(model), integrator, {});
  sim.start();
  double theta = -1;
  while (sim.world().time < 0.4 && theta < 0) {
    sim.step();
    const Vec3 x = sim.world().particles.position[0];
    const double from_vertical = std::atan2(a - x.x, x.z);
    if (from_vertical > 0.2 && sim.world().particles.contact_count[0] == 0) theta = from_vertical;  // off the rim
  }
  std::printf("left the rim at %.4f degrees (cos theta = %.5f)\n", theta * 180 / M_PI, std::cos(theta));
  EXPECT_NEAR(std::cos(theta), 2.0 / 3.0, 3e-3);
}

TEST(HoleInAPlane, AFrictionlessBallSlidesOffTheRimWhereCosThetaIsTwoThirds) {
  slides_off_the_rim(Integrator::velocity_verlet, 1e-6);
}
TEST(CurvedWallBlockSteps, AFrictionlessBallSlidesOffTheRimWhereCosThetaIsTwoThirds) {
  slides_off_the_rim(Integrator::block_hermite, 1e-5);
}

// Block steps with walls that are not whole planes (cylinders, cones, a plane's hole): the
// touch on Dual numbers (Wall::touch_on) has the value of the touch on double, to the bit,
// and the exact rates of the distance and the normal (against central differences along the
// centre's path), and a turning drum's surface velocity the rate of the point under the
// grain; a ball rolling in a turning drum follows velocity Verlet's path.
Wall cone(bool inside) {  // a hopper at 45 degrees, from r = 0.01 m at z = 0 to 0.05 m at z = 0.04 m
  Wall w;
  w.shape = WallShape::cone;
  w.axis = {0, 0, 1};
  w.radius = 0.01;
  w.end_radius = 0.05;
  w.length = 0.04;
  w.inside = inside;
  return w;
}

Wall plate_with_hole() {
  Wall w;
  w.normal = {0, 0, 1};
  w.hole_radius = 0.01;
  return w;
}

// The touch on Dual of a centre at x moving at v: its value is the touch on double, bit for
// bit; its rates are the central differences of the touch along the path (to h^2: 1e-7 of the
// rate with h = 1e-6 s over the walls' centimetres).
void expect_exact_rates(const Wall& wall, const Vec3& x, const Vec3& v, const char* what) {
  const BasicWallTouch<Dual> t = wall.touch_on<Dual>(DualVec3(x, v));
  const WallTouch at = wall.touch(x);
  EXPECT_EQ(value(t.distance), at.distance) << what;
  EXPECT_EQ(value(t.normal), at.normal) << what;
  const double h = 1e-6;
  const WallTouch ahead = wall.touch(x + h * v), behind = wall.touch(x - h * v);
  const double distance_rate = (ahead.distance - behind.distance) / (2 * h);
  const Vec3 normal_rate = (ahead.normal - behind.normal) / (2 * h);
  std::printf("%s: distance rate %.9g (difference %.9g), normal rate |%.6g| (difference off by %.3g)\n", what, t.distance.d,
              distance_rate, norm(rate(t.normal)), norm(rate(t.normal) - normal_rate));
  EXPECT_NEAR(t.distance.d, distance_rate, 1e-7 * norm(v)) << what;
  EXPECT_GT(norm(rate(t.normal)), 1.0) << what;  // the normal does turn along these paths
  EXPECT_LT(norm(rate(t.normal) - normal_rate), 1e-6 * norm(rate(t.normal))) << what;
}

TEST(CurvedWallRates, TheTouchOnDualHasTheExactRatesOfTheDistanceAndTheNormal) {
  const Vec3 v{0.3, -0.2, 0.5};
  expect_exact_rates(cylinder(0.1, true), {0.03, 7.0, -0.04}, v, "inside a cylinder");
  expect_exact_rates(cylinder(0.1, false), {0.09, 0.2, -0.08}, v, "outside a cylinder");
  expect_exact_rates(cone(true), {0.02, 0.01, 0.02}, v, "inside a cone, over its face");
  expect_exact_rates(cone(false), {0.03, 0.02, 0.01}, v, "outside a cone, over its face");
  expect_exact_rates(cone(true), {0.004, 0.003, -0.004}, v, "below a cone's outlet rim");
  expect_exact_rates(cone(true), {0.045, 0.01, 0.046}, v, "above a cone's top rim");
  expect_exact_rates(plate_with_hole(), {0.007, 0.001, 0.004}, v, "over a hole, at its rim");
}

// A turning drum's surface under a moving grain: the central difference of the surface's
// velocity at the nearest point along the path.
TEST(CurvedWallRates, ATurningDrumsSurfaceVelocityHasTheRateOfThePointUnderTheGrain) {
  Wall drum = cylinder(0.1, true);
  drum.angular_velocity = {0, 2, 0};
  const Vec3 x{0.03, 0.01, -0.06}, v{0.4, 0.1, -0.3};
  const DualVec3 s = surface_velocity<Dual>(drum, Motion<Dual>{x, DualVec3(v, {}), DualVec3()}, drum.touch(x));
  const double h = 1e-6;
  const Vec3 difference = (drum.surface_velocity_at(x + h * v) - drum.surface_velocity_at(x - h * v)) / (2 * h);
  std::printf("rate |%.6g|, off the difference by %.3g\n", norm(rate(s)), norm(rate(s) - difference));
  EXPECT_EQ(value(s), drum.surface_velocity_at(x));
  EXPECT_LT(norm(rate(s) - difference), 1e-7 * norm(difference));
}

// A plate with a hole, moving and turning about the hole's centre (which moves with it): the
// surface's velocity on the rim under a moving grain has the rate of the rim point relative
// to the moving axis, omega x (p' - V), the central difference along the path, the plate
// moving with it.
TEST(CurvedWallRates, AMovingTurningRimsSurfaceVelocityHasTheRateOfThePointUnderTheGrain) {
  Wall plate = plate_with_hole();
  plate.velocity = {0.2, -0.1, 0.3};
  plate.angular_velocity = {0, 0, 4};
  const Vec3 x{0.007, 0.001, 0.004}, v{0.4, 0.1, -0.3};
  const DualVec3 s = surface_velocity<Dual>(plate, Motion<Dual>{x, DualVec3(v, {}), DualVec3()}, plate.touch(x));
  const double h = 1e-6;
  auto at = [&](double t) {
    Wall moved = plate;
    moved.point += t * plate.velocity;
    return moved.surface_velocity_at(x + t * v);
  };
  const Vec3 difference = (at(h) - at(-h)) / (2 * h);
  std::printf("rate |%.6g|, off the difference by %.3g\n", norm(rate(s)), norm(rate(s) - difference));
  EXPECT_LT(norm(rate(s) - difference), 1e-7 * norm(difference));
}

// A ball with Mindlin friction set on the inside of a drum turning at 3 rad/s is dragged up
// its side: block steps (dt = 0.2 ms) and velocity Verlet (dt = 1 us) give the same path over
// 0.2 s to within the fixed step's error (the surface's velocity and the normal turning under
// the rolling ball, with their rates).
TEST(CurvedWallBlockSteps, ABallInATurningDrumFollowsVelocityVerletsPath) {
  const double R = 0.05, r = 0.004;
  auto path = [&](Integrator integrator, double dt) {
    auto [world, model] = testing::make_world({"glass", 2500, 1e8, 0.3}, testing::spec_of("hertz_tsuji", "mindlin", 0.5, 0.5),
                                              dt, {0, 0, -9.81});
    Wall drum = cylinder(R, true);
    drum.angular_velocity = {0, 3, 0};
    world.walls.push_back(drum);
    world.particles.add(0, 0, 2 * r, 2500, {0, 0, -(R - r) + 2e-6}, {});
    Simulation sim(std::move(world), std::move(model), integrator, {});
    sim.start();
    sim.advance_to(std::llround(0.2 / dt));
    return sim.world().particles;
  };
  const Particles block = path(Integrator::block_hermite, 2e-4), verlet = path(Integrator::velocity_verlet, 1e-6);
  const double climbed = std::atan2(verlet.position[0].x, -verlet.position[0].z);  // rad up the side
  std::printf("climbed %.4f rad; block - Verlet: %.3g m, %.3g m/s, %.3g rad/s\n", climbed,
              norm(block.position[0] - verlet.position[0]), norm(block.velocity[0] - verlet.velocity[0]),
              norm(block.omega[0] - verlet.omega[0]));
  EXPECT_GT(std::abs(climbed), 0.03);
  EXPECT_LT(norm(block.position[0] - verlet.position[0]), 1e-6);
  EXPECT_LT(norm(block.velocity[0] - verlet.velocity[0]), 1e-4);
}

// A moving cylinder or cone (`motion`: a lifted tube, a moving hopper) acts as the still one
// seen from the wall: a ball with Mindlin friction and spin in a turning drum, or sliding down
// a hopper's face, started at the wall's velocity V, keeps its path relative to the wall, x - V t,
// and its velocity less V, as in the still wall's run, to round-off; with velocity Verlet
// and with block steps.
void moves_as_in_the_still_wall(Integrator integrator, double dt) {
  const Vec3 V{0.2, 0.3, -0.1}, g{0, 0, -9.81};
  Wall drum = cylinder(0.05, true);
  drum.angular_velocity = {0, 3, 0};
  Wall hopper;
  hopper.shape = WallShape::cone;
  hopper.point = {0, 0, 0}, hopper.axis = {0, 0, 1};
  hopper.radius = 0.01, hopper.end_radius = 0.03, hopper.length = 0.02;
  const double r = 0.004;
  // On the drum's floor; on the hopper's face, along its inward normal from the face's middle.
  const Vec3 on_floor{0, 0, -(0.05 - r) + 2e-6};
  const Vec3 on_face = Vec3{0.02, 0, 0.01} + (r - 1e-6) * Vec3{-1, 0, 1} / std::sqrt(2.0);  // the face at 45 degrees
  for (const auto& [wall, start] : {std::pair{drum, on_floor}, std::pair{hopper, on_face}}) {
    auto run = [&](const Vec3& velocity) {
      auto [world, model] = testing::make_world({"glass", 2500, 1e8, 0.3}, testing::spec_of("hertz_tsuji", "mindlin", 0.5, 0.5),
                                                dt, g);
      Wall w = wall;
      if (!(velocity == Vec3{})) w.motion = {{1.0, velocity}};
      world.walls.push_back(w);
      world.particles.add(0, 0, 2 * r, 2500, start, velocity);
      world.particles.omega[0] = {5, -3, 2};
      Simulation sim(std::move(world), std::move(model), integrator, {});
      sim.start();
      sim.advance_to(std::llround(0.05 / dt));
      return std::pair{sim.world().particles, sim.world().time};
    };
    const auto [moving, t] = run(V);
    const auto [still, t_still] = run({});
    const Vec3 dx = moving.position[0] - t * V - still.position[0], dv = moving.velocity[0] - V - still.velocity[0];
    std::printf("%s, moving against still: %.3g m, %.3g m/s, %.3g rad/s; moved %.4g m on the wall\n",
                wall.shape == WallShape::cone ? "hopper" : "drum", norm(dx), norm(dv), norm(moving.omega[0] - still.omega[0]),
                norm(still.position[0] - start));
    EXPECT_GT(still.contact_count[0], 0);
    EXPECT_GT(norm(still.position[0] - start), 1e-4);
    EXPECT_LT(norm(dx), 1e-12);
    EXPECT_LT(norm(dv), 1e-10);
    EXPECT_LT(norm(moving.omega[0] - still.omega[0]), 1e-7);
  }
}
TEST(CylinderWall, AMovingCylinderOrConeActsAsTheStillOneSeenFromIt) { moves_as_in_the_still_wall(Integrator::velocity_verlet, 1e-6); }
TEST(CurvedWallBlockSteps, AMovingCylinderOrConeActsAsTheStillOneSeenFromIt) {
  moves_as_in_the_still_wall(Integrator::block_hermite, 2e-4);
}

}  // namespace
}  // namespace tsubu
