// A wall's surface motion within its plane (docs/scenario.md, [[walls]] surface_velocity and
// angular_velocity): a sphere dropped on a conveyor belt ends rolling at 2/7 of the belt's
// speed, with velocity Verlet and with block steps; a turntable drives it as a belt of the
// surface's local speed; a wall whose surface stands still gives the bits it gave before.
// In stretches (surface_motion): a belt in one stretch is the constant belt to the bit, and
// a sphere rolling on a belt that stops comes to rest with it.
#include <gtest/gtest.h>

#include <cstdio>

#include "scenario_run.hpp"
#include "tsubu/forces/evaluate.hpp"

namespace tsubu {
namespace {

using testing::run_test_scenario;

constexpr double kBelt = 0.1, kRadius = 0.005;

// Slipping, kinetic friction mu N accelerates the sphere (m dv/dt = mu N) and spins it
// against the belt (I dw/dt = R mu N, I = 2/5 m R^2): the slip falls at 7/2 mu g until the
// contact point moves with the belt, v - R w_y = v_belt, at v = 2/7 v_belt, whatever the
// bounces after the drop do to N. The contact's elastic overlap shortens the lever arm by a
// part in 10^4 and the tangential spring's oscillation is damped out: 2e-3 covers both.
void expect_rolling_at_two_sevenths(const World& w, const char* what) {
  const Vec3 v = w.particles.velocity[0], spin = w.particles.omega[0];
  std::printf("%s: v = %.7f m/s (2/7 v_belt = %.7f), contact point %.7f m/s (belt %.2f)\n", what, v.x, 2.0 / 7.0 * kBelt,
              v.x - kRadius * spin.y, kBelt);
  EXPECT_NEAR(v.x / (2.0 / 7.0 * kBelt), 1.0, 2e-3) << what;
  EXPECT_NEAR((v.x - kRadius * spin.y) / kBelt, 1.0, 2e-3) << what;
  EXPECT_NEAR(v.y, 0.0, 1e-12) << what;
}

TEST(WallSurface, ASphereOnABeltRollsAtTwoSeventhsOfItsSpeed) {
  expect_rolling_at_two_sevenths(run_test_scenario("belt.toml"), "velocity Verlet");
  expect_rolling_at_two_sevenths(
      run_test_scenario("belt.toml", {"simulation.integrator=\"block_hermite\"", "simulation.dt=1e-3"}), "block steps");
}

// A conveyor of triangles (tests/scenarios/belt_mesh.toml: a flat mesh of 800 triangles of
// 1 mm under the 1 cm sphere, its surface moving at the belt's 0.1 m/s) is the plane belt: the
// sphere, touching faces, edges and vertices as it rolls over them, ends at the plane run's
// place and speed to round-off, with velocity Verlet and with block steps.
TEST(WallSurface, AConveyorOfTrianglesIsThePlaneBelt) {
  for (const char* integrator : {"velocity_verlet", "block_hermite"}) {
    std::vector<std::string> sets = {std::string("simulation.integrator=\"") + integrator + "\""};
    if (std::string(integrator) == "block_hermite") sets.push_back("simulation.dt=1e-3");
    const World plane = run_test_scenario("belt.toml", sets), mesh = run_test_scenario("belt_mesh.toml", sets);
    expect_rolling_at_two_sevenths(mesh, integrator);
    const Vec3 dx = mesh.particles.position[0] - plane.particles.position[0];
    const Vec3 dv = mesh.particles.velocity[0] - plane.particles.velocity[0];
    const Vec3 dw = mesh.particles.omega[0] - plane.particles.omega[0];
    std::printf("%s: the mesh belt's sphere off the plane's by %.3g m, %.3g m/s, %.3g rad/s (it moved %.4f mm)\n", integrator,
                norm(dx), norm(dv), norm(dw), 1e3 * plane.particles.position[0].x);
    EXPECT_GT(plane.particles.position[0].x, 1e-3) << "over several triangles";
    EXPECT_LT(norm(dx), 1e-12) << integrator;
    EXPECT_LT(norm(dv), 1e-10) << integrator;
    EXPECT_LT(norm(dw), 1e-8) << integrator;
  }
}

// A turntable turning at 10 rad/s about the vertical through (0, 0.01, 0) moves its surface
// under the sphere at (0, 0, .) at 0.1 m/s along x, a velocity that stays where it is: in the
// 3.5 ms between the landing (4.5 ms after the drop) and 8 ms the sphere moves some 0.1 mm,
// 1 % of its distance from the axis, and the table drives it as the belt does to that order.
TEST(WallSurface, ATurntableDrivesASphereAsABeltOfItsLocalSpeed) {
  const std::vector<std::string> turntable = {"walls.0.surface_velocity=[0, 0, 0]", "walls.0.angular_velocity=[0, 0, 10]",
                                              "walls.0.center=[0, 0.01, 0]"};
  for (const char* integrator : {"velocity_verlet", "block_hermite"}) {
    std::vector<std::string> sets = {std::string("simulation.integrator=\"") + integrator + "\"", "simulation.duration=0.008"};
    if (std::string(integrator) == "block_hermite") sets.push_back("simulation.dt=1e-3");
    const World belt = run_test_scenario("belt.toml", sets);
    sets.insert(sets.end(), turntable.begin(), turntable.end());
    const World table = run_test_scenario("belt.toml", sets);
    const Vec3 a = belt.particles.velocity[0], b = table.particles.velocity[0];
    std::printf("%s: after 8 ms on the belt v = (%.4g, %.4g) m/s, on the turntable (%.4g, %.4g) m/s\n", integrator, a.x, a.y,
                b.x, b.y);
    ASSERT_GT(a.x, 1e-3) << integrator;  // the belt has driven it
    EXPECT_NEAR(b.x / a.x, 1.0, 1e-2) << integrator;
    EXPECT_LT(std::abs(b.y), 1e-2 * a.x) << integrator;
  }
}

// The belt of belt_stops.toml runs in one stretch until 0.03 s: before then it is the
// constant belt of belt.toml, bit for bit.
TEST(WallSurface, ABeltInOneStretchIsTheConstantBelt) {
  const World constant = run_test_scenario("belt.toml", {"simulation.duration=0.02"});
  const World stretch = run_test_scenario("belt_stops.toml", {"simulation.duration=0.02"});
  EXPECT_TRUE(testing::same_particle_bits(constant, stretch));
}

// Rolling at 2/7 of the belt's speed, the sphere has no angular momentum about its contact
// point (m R v + I w_y = m R vb (2/7 - 2/5 5/7) = 0), which friction, acting at that point,
// cannot change: when the belt stops at 0.03 s, the sphere slips to rest. 2e-3 of its
// rolling speed allows for the contact's lever arm, as above. With velocity Verlet and with
// block steps (whose steps end at the stop: no step straddles it).
TEST(WallSurface, ASphereRollingOnABeltStopsWhenTheBeltStops) {
  for (const char* integrator : {"velocity_verlet", "block_hermite"}) {
    std::vector<std::string> sets = {std::string("simulation.integrator=\"") + integrator + "\""};
    if (std::string(integrator) == "block_hermite") sets.push_back("simulation.dt=1e-3");
    std::vector<std::string> until_stop = sets;
    until_stop.push_back("simulation.duration=0.03");
    const World rolling = run_test_scenario("belt_stops.toml", until_stop);
    const World stopped = run_test_scenario("belt_stops.toml", sets);
    const Vec3 v0 = rolling.particles.velocity[0], v = stopped.particles.velocity[0], w = stopped.particles.omega[0];
    std::printf("%s: at 0.03 s v = %.6f m/s; at 0.06 s v = %.3g m/s, R w_y = %.3g m/s\n", integrator, v0.x, v.x, kRadius * w.y);
    EXPECT_NEAR(v0.x / (2.0 / 7.0 * kBelt), 1.0, 2e-3) << integrator;
    EXPECT_LT(std::abs(v.x), 2e-3 * 2.0 / 7.0 * kBelt) << integrator;
    EXPECT_LT(std::abs(kRadius * w.y), 2e-3 * 2.0 / 7.0 * kBelt) << integrator;
  }
}

// On Dual the surface's velocity carries the rate of a turning surface under a moving
// particle, the angular velocity times the particle's velocity: the central difference of
// surface_velocity_at along the particle's path (exact, the velocity being linear in x).
TEST(WallSurface, ATurningSurfacesVelocityHasTheRateOfThePathOverIt) {
  Wall w;
  w.normal = {0, 0, 1};
  w.angular_velocity = {0, 0, 3};
  w.axis_offset = {0.2, -0.1, 0};
  const Vec3 x{0.3, 0.4, 0.01}, v{1.5, -0.7, 0.2};
  const DualVec3 s = surface_velocity<Dual>(w, Motion<Dual>{x, DualVec3(v, {}), DualVec3()}, w.touch(x));
  const double h = 1e-3;
  const Vec3 difference = (w.surface_velocity_at(x + h * v) - w.surface_velocity_at(x - h * v)) / (2 * h);
  const Vec3 rate{s.x.d, s.y.d, s.z.d};
  EXPECT_LT(norm(rate - difference), 1e-12 * norm(difference));
  EXPECT_LT(norm(value(s) - w.surface_velocity_at(x)), 1e-15);
  w.angular_velocity = {};  // a surface at rest: the wall's own velocity, its rate zero
  w.velocity = {0, 0, -0.2};
  const DualVec3 still = surface_velocity<Dual>(w, Motion<Dual>{x, DualVec3(v, {}), DualVec3()}, w.touch(x));
  EXPECT_EQ(value(still), w.velocity);
  EXPECT_EQ(Vec3(still.x.d, still.y.d, still.z.d), Vec3{});
}

}  // namespace
}  // namespace tsubu
