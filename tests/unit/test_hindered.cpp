// Hindered settling (docs/engine.md, "Hindered settling"): the ball volumes against numerical
// integration, the Richardson-Zaki exponent and terminal speed, the hindered drag and its
// exact rate, the local solid fraction of the force field against Monte Carlo, and a
// suspension settling at the Richardson-Zaki speed with fixed and with block steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tsubu/core/random.hpp"
#include "tsubu/fluid/crowding.hpp"
#include "tsubu/integrate/block_hermite.hpp"
#include "tsubu/search/pair_search.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

constexpr double kRhoP = 2650, kRhoF = 1000, kNu = 1e-6, kG = 9.81;

// Simpson's rule on n (even) intervals.
template <class F>
double simpson(F f, double a, double b, int n = 20000) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int k = 1; k < n; ++k) s += (k % 2 ? 4 : 2) * f(a + k * h);
  return s * h / 3;
}

// Independent volumes: slices perpendicular to the line of centres, each the smaller of the
// two discs (both centred on that line).
double lens_by_slices(double R, double r, double dist) {
  const double lo = std::max(-R, dist - r), hi = std::min(R, dist + r);
  if (hi <= lo) return 0;
  auto area = [&](double z) { return M_PI * std::max(0.0, std::min(R * R - z * z, r * r - (z - dist) * (z - dist))); };
  if (dist == 0) return simpson(area, lo, hi);
  // Split where the smaller disc changes (the plane where the spheres meet), a kink.
  const double x = std::clamp((dist * dist + R * R - r * r) / (2 * dist), lo, hi);
  return simpson(area, lo, x) + simpson(area, x, hi);
}

TEST(HinderedVolumes, LensAgainstSlicesAndItsSlopeAgainstDifferences) {
  for (double R : {1.0, 3.0})
    for (double r : {0.4, 1.0, 2.5})
      for (double dist = R == r ? 0.137 : 0; dist < R + r + 0.5; dist += 0.137) {  // equal and concentric: a kink
        const VolumeSlope v = lens_volume(R, r, dist);
        EXPECT_NEAR(v.volume, lens_by_slices(R, r, dist), 1e-9 * R * R * R) << R << " " << r << " " << dist;
        const double h = 1e-6;
        const double slope = (lens_volume(R, r, dist + h).volume - lens_volume(R, r, std::max(0.0, dist - h)).volume) /
                             (dist + h - std::max(0.0, dist - h));
        EXPECT_NEAR(v.slope, slope, 1e-6 * R * R) << R << " " << r << " " << dist;
      }
}

TEST(HinderedVolumes, CapAgainstIntegralAndItsSlopeAgainstDifferences) {
  const double R = 2;
  for (double dist = -2.5; dist < 2.5; dist += 0.093) {
    const VolumeSlope c = cap_volume(R, dist);
    const double lo = std::max(-R, dist);
    const double expected = lo >= R ? 0 : simpson([&](double z) { return M_PI * (R * R - z * z); }, lo, R);
    EXPECT_NEAR(c.volume, expected, 1e-9) << dist;
    const double h = 1e-6;
    EXPECT_NEAR(c.slope, (cap_volume(R, dist + h).volume - cap_volume(R, dist - h).volume) / (2 * h), 1e-6) << dist;
  }
}

// The part of a ball (radius R, centre rho from the axis) beyond the surface of a cylinder of
// radius Rc, independently: over the cylinder's cross-section in polar coordinates (r, theta)
// about its axis, the ball's extent along the axis, 2 sqrt(R^2 - q^2) with q the distance in
// the section from the ball's centre; Simpson in both (the region behind: r > Rc for a grain
// inside, r < Rc outside), theta only where the ball is. Its own accuracy, from its square
// roots' kinks: about 1e-5 R^3 (halving its steps moves it by that much).
double cylinder_cut_by_integral(double R, double Rc, double rho, bool inside) {
  const double lo = inside ? std::max(Rc, rho - R) : std::max(0.0, rho - R);
  const double hi = inside ? rho + R : std::min(Rc, rho + R);
  if (hi <= lo) return 0;
  auto ring = [&](double r) {
    // theta up to where the ring leaves the ball: cos(theta) = (r^2 + rho^2 - R^2) / (2 r rho)
    const double c = r * rho > 0 ? (r * r + rho * rho - R * R) / (2 * r * rho) : -1.0;
    const double top = c <= -1 ? M_PI : c >= 1 ? 0 : std::acos(c);
    return r * simpson([&](double t) { return 2 * std::sqrt(std::max(0.0, R * R - (r * r + rho * rho - 2 * r * rho * std::cos(t)))); },
                       0, top, 1000);
  };
  return 2 * simpson(ring, lo, hi, 1000);  // theta in (-top, top): twice (0, top)
}

// Inside and outside cylinders from narrower than the ball to 100 times wider, grains from
// beyond the surface (a centre behind it, which no run reaches) to out of reach: the volume
// against the independent integral, its slope against central differences, and a very wide
// cylinder against the plane's cap.
TEST(HinderedVolumes, CylinderCutAgainstAnIntegralAndItsSlopeAgainstDifferences) {
  const double R = 1;
  double worst = 0;
  for (const bool inside : {true, false})
    for (const double Rc : {0.8, 1.5, 4.0, 100.0})
      for (double dist = -0.9; dist < 1.1; dist += 0.17) {
        if (inside ? dist > Rc : dist < -Rc) continue;  // the centre beyond the axis
        const VolumeSlope v = cylinder_cut_volume(R, Rc, dist, inside);
        const double rho = inside ? Rc - dist : Rc + dist;
        const double reference = cylinder_cut_by_integral(R, Rc, rho, inside);
        worst = std::max(worst, std::abs(v.volume - reference));
        EXPECT_NEAR(v.volume, reference, 1e-4) << inside << " " << Rc << " " << dist;
        const double h = Rc > 10 ? 1e-4 : 1e-6;  // a wide cylinder's areas are differences of large ones
        const double slope =
            (cylinder_cut_volume(R, Rc, dist + h, inside).volume - cylinder_cut_volume(R, Rc, dist - h, inside).volume) / (2 * h);
        EXPECT_NEAR(v.slope, slope, 1e-6 * (Rc > 10 ? 100 : 1)) << inside << " " << Rc << " " << dist;
        if (Rc == 100.0) EXPECT_NEAR(v.volume, cap_volume(R, dist).volume, 0.02 * cap_volume(R, dist).volume + 1e-12);
      }
  std::printf("largest difference from the independent integral: %.2g R^3\n", worst);
  EXPECT_EQ(cylinder_cut_volume(R, 4.0, 1.0, true).volume, 0.0);
  EXPECT_EQ(cylinder_cut_volume(R, 4.0, -1.0, false).volume, ball_volume(R));
}

// drag(u) = (rho_p - rho_f) V g solved by bisection, independently of fluid.cpp's Newton.
double terminal_by_bisection(double d) {
  const double area = M_PI * d * d / 4, weight = (kRhoP - kRhoF) * M_PI * d * d * d / 6 * kG;
  auto drag = [&](double u) {
    const double re = u * d / kNu, cd = re <= 1000 ? 24 / re * (1 + 0.15 * std::pow(re, 0.687)) : 0.44;
    return 0.5 * cd * kRhoF * area * u * u;
  };
  double lo = 0, hi = 100;
  for (int k = 0; k < 200; ++k) (drag(0.5 * (lo + hi)) < weight ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

Fluid water(bool hindered) {
  Fluid f;
  f.enabled = true;
  f.density = kRhoF;
  f.viscosity = kNu;
  f.hindered = hindered;
  return f;
}

TEST(HinderedSettling, TerminalSpeedAndRichardsonZakiExponent) {
  const Fluid f = water(true);
  for (double d : {1e-5, 1e-4, 1e-3, 1e-2, 5e-2}) {
    const double expected = terminal_by_bisection(d);
    // Between Re C_D at 1000 by the formula (438.6...) and 0.44 1000 the drag law has a step:
    // no root; both land on Re = 1000 there. Elsewhere the same root.
    EXPECT_NEAR(terminal_speed(f, kRhoP, d, kG), expected, 1e-12 * expected + 1e-15) << d;
  }
  EXPECT_EQ(terminal_speed(f, 900, 1e-3, kG), 0.0);  // lighter than water: no settling
  EXPECT_EQ(richardson_zaki_exponent(0.05), 4.65);
  EXPECT_DOUBLE_EQ(richardson_zaki_exponent(0.5), 4.4 * std::pow(0.5, -0.03));
  EXPECT_DOUBLE_EQ(richardson_zaki_exponent(50), 4.4 * std::pow(50.0, -0.1));
  EXPECT_EQ(richardson_zaki_exponent(5000), 2.39);
}

TEST(HinderedSettling, TheDragIsTheLoneGrainsAtTheScaledVelocity) {
  const Fluid plain = water(false), hindered = water(true);
  const double d = 1e-3;
  const Crowding crowd{0.3, 0, 3.1};
  const double s = std::pow(0.7, -3.1);
  for (double speed : {0.0, 1e-4, 0.05, 0.3, 2.0}) {
    const Vec3 u{0.3 * speed, -0.1 * speed, -speed};
    const Vec3 expected = fluid_load(plain, d, {}, s * u, {}).force;
    const Vec3 got = fluid_load(hindered, d, {}, u, {}, crowd).force;
    EXPECT_NEAR(norm(got - expected), 0, 1e-13 * (norm(expected) + 1e-12)) << speed;
  }
  // The rate at rest: the Stokes drag's, scaled.
  const Vec3 a{0, 0, -3};
  EXPECT_NEAR(norm(fluid_load_rate(hindered, d, {}, a, {}, {}, crowd).force - s * fluid_load_rate(plain, d, {}, a, {}, {}).force), 0,
              1e-15);
  // Without hindered_settling the crowding is ignored.
  EXPECT_EQ(fluid_load(plain, d, {}, {0, 0, -0.1}, {}, crowd).force.z, fluid_load(plain, d, {}, {0, 0, -0.1}, {}).force.z);
}

// The jerk of the hindered drag along u(t) = u0 + a t, phi(t) = phi0 + phidot t against
// central differences: exact to the differences' own error.
TEST(HinderedSettling, TheDragRateIsExact) {
  const Fluid f = water(true);
  const double d = 2e-3;
  for (double speed : {1e-3, 0.1, 1.0}) {
    const Vec3 u0{0.2 * speed, 0.1 * speed, -speed}, a{0.5, -0.2, -4};
    const double phi0 = 0.25, phidot = 3.0, n = 3.3;
    auto force = [&](double t) {
      return fluid_load(f, d, {}, u0 + t * a, {}, Crowding{phi0 + phidot * t, phidot, n}).force;
    };
    const double h = 1e-7;  // the differences' truncation error ~ h^2, about 2e-9 relative at the slowest
    const Vec3 numeric = (force(h) - force(-h)) / (2 * h);
    const Vec3 exact = fluid_load_rate(f, d, u0, a, {}, {}, Crowding{phi0, phidot, n}).force;
    EXPECT_NEAR(norm(exact - numeric), 0, 1e-7 * norm(exact)) << speed;
  }
}

// The suspension's solid fraction from a ball's content solves its equation; a lone grain
// sees none.
TEST(HinderedVolumes, SuspensionFractionSolvesTheCorrelationHoleEquation) {
  const double own = 1, room = 27;
  EXPECT_EQ(suspension_fraction(0, 0, room, 0, own).solid_fraction, 0.0);
  for (double solid : {0.01, 0.5, 3.0, 8.0, 15.0}) {
    const double phi = suspension_fraction(solid, 0, room, 0, own).solid_fraction;
    const double s = std::pow(1 - phi, 4) / std::pow(1 + 2 * phi, 2);
    EXPECT_NEAR(phi * room, solid + own * (1 - s), 1e-12 * room) << solid;
    EXPECT_GT(phi, solid / room);
    // The rate: the change of phi with the content and the room.
    const double h = 1e-6, rate = suspension_fraction(solid, 2.0, room, -1.0, own).rate;
    const double numeric = (suspension_fraction(solid + 2 * h, 0, room - h, 0, own).solid_fraction -
                            suspension_fraction(solid - 2 * h, 0, room + h, 0, own).solid_fraction) / (2 * h);
    EXPECT_NEAR(rate, numeric, 1e-7 * std::abs(rate)) << solid;
  }
}

// Grains in a periodic box with a floor: the force field's solid fraction around each grain
// against Monte Carlo points (the other grains' share of the ball in front of the floor,
// corrected as suspension_fraction does), and its rate against
// the change when every grain moves on by v h.
TEST(HinderedSettling, TheLocalSolidFractionAgainstMonteCarlo) {
  auto [w, model] = testing::make_world({"quartz", kRhoP, 1e7, 0.17}, testing::spec_of("hertz_tsuji", "none", 0.5), 1e-6);
  w.domain = {{0, 0, 0}, {0.02, 0.02, 0.05}, {true, true, false}};
  w.walls.push_back({{0, 0, 0}, {0, 0, 1}});
  model.fluid = water(true);
  Random rng(7);
  while (w.particles.size() < 150) {
    const double d = 0.001 + 0.0015 * rng.uniform();
    const Vec3 x{0.02 * rng.uniform(), 0.02 * rng.uniform(), d / 2 + 0.03 * rng.uniform()};
    bool free = true;
    for (std::size_t j = 0; j < w.particles.size() && free; ++j)
      free = norm(w.domain.separation(x, w.particles.position[j])) > w.particles.radius[j] + d / 2;
    if (free)
      w.particles.add(static_cast<std::int64_t>(w.particles.size()), 0, d, kRhoP, x,
                      {0.1 * rng.uniform() - 0.05, 0.1 * rng.uniform() - 0.05, -0.2 * rng.uniform()});
  }
  ForceField forces(model);
  forces.compute(w);
  const Particles& p = w.particles;
  for (std::size_t i : {0u, 17u, 42u, 99u, 140u}) {
    const double R = 3 * p.radius[i], own = 4.0 / 3.0 * M_PI * std::pow(p.radius[i], 3);
    int inside = 0, filled = 0;
    for (int k = 0; k < 40000; ++k) {
      const Vec3 y = p.position[i] + R * Vec3{2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
      if (norm(y - p.position[i]) > R || y.z < 0) continue;
      ++inside;
      for (std::size_t j = 0; j < p.size(); ++j)
        if (j != i && norm(w.domain.separation(w.domain.wrap(y), p.position[j])) < p.radius[j]) {
          ++filled;
          break;
        }
    }
    const double room = 4.0 / 3.0 * M_PI * R * R * R - cap_volume(R, p.position[i].z).volume;
    const double share = double(filled) / inside, se = std::sqrt(share * (1 - share) / inside);
    const double expected = suspension_fraction(share * room, 0, room, 0, own).solid_fraction;
    const Crowding c = forces.crowding(i);
    std::printf("grain %zu at z = %.4f m: others fill %.4f +- %.4f of the ball: phi %.4f, expected %.4f\n", i,
                p.position[i].z, share, se, c.solid_fraction, expected);
    EXPECT_NEAR(c.solid_fraction, expected, 5 * se + 1e-3);
  }
  // The rate (velocity Verlet needs none and leaves it 0; block steps take it): a crowd list
  // of its own, against moving every grain on by v h.
  EXPECT_EQ(forces.crowding(42).rate, 0.0);
  auto crowds = [&](const World& at) {
    Particles balls = at.particles;
    for (double& r : balls.radius) r *= 3;
    std::vector<Pair> pairs;
    CellGrid().find_pairs(balls, at.domain, 0.0, pairs);
    CrowdList list;
    list.build(at, model.fluid, norm(model.gravity), pairs);
    std::vector<Crowding> out(at.particles.size());
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = list.of<true>(at, i, [&](std::size_t j) { return PointMotion{at.particles.position[j], at.particles.velocity[j]}; });
    return out;
  };
  const std::vector<Crowding> now = crowds(w);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(now[i].solid_fraction, forces.crowding(i).solid_fraction);
  const double h = 1e-7;
  World moved = w;
  for (std::size_t i = 0; i < p.size(); ++i) moved.particles.position[i] = w.domain.wrap(p.position[i] + h * p.velocity[i]);
  const std::vector<Crowding> later = crowds(moved);
  double worst = 0, largest = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    worst = std::max(worst, std::abs((later[i].solid_fraction - now[i].solid_fraction) / h - now[i].rate));
    largest = std::max(largest, std::abs(now[i].rate));
  }
  std::printf("largest |dphi/dt| %.3g 1/s, worst difference from the finite difference %.3g 1/s\n", largest, worst);
  EXPECT_GT(largest, 0.1);
  EXPECT_LT(worst, 1e-4 * largest);
}

// Grains in a vertical pipe (a cylinder wall, the grains inside): the solid fraction of the
// force field around grains near the pipe's wall against Monte Carlo, the room being the ball
// less what lies beyond the wall.
// A cone about the z axis through the origin, from radius r0 at z = 0 to r1 at z = length.
Wall cone_wall(double r0, double r1, double length, bool inside) {
  Wall w;
  w.shape = WallShape::cone;
  w.axis = {0, 0, 1};
  w.radius = r0, w.end_radius = r1, w.length = length;
  w.inside = inside;
  return w;
}

// Whether the point y lies behind the cone (between its ends, beyond its surface from the
// particles' side).
bool behind_cone(const Wall& w, const Vec3& y) {
  const double s = y.z, c = w.radius + (w.end_radius - w.radius) * s / w.length, rho = std::hypot(y.x, y.y);
  return s >= 0 && s <= w.length && (w.inside ? rho > c : rho < c);
}

// The part of a ball (radius R, centre x) behind a cone, independently: slices across the
// axis (Simpson in z), each slice's part behind by rings about the axis (r, theta), as in
// cylinder_cut_by_integral. Its own accuracy: about 1e-5 R^3.
double cone_cut_by_integral(const Wall& w, double R, const Vec3& x) {
  const double rho = std::hypot(x.x, x.y);
  const double lo = std::max(x.z - R, 0.0), hi = std::min(x.z + R, w.length);
  if (hi <= lo) return 0;
  auto slice = [&](double z) {
    const double a2 = R * R - (z - x.z) * (z - x.z);
    if (a2 <= 0) return 0.0;
    const double a = std::sqrt(a2), c = w.radius + (w.end_radius - w.radius) * z / w.length;
    const double r_lo = w.inside ? std::max(c, rho - a) : std::max(0.0, rho - a), r_hi = w.inside ? rho + a : std::min(c, rho + a);
    if (r_hi <= r_lo) return 0.0;
    auto ring = [&](double r) {
      const double cos_top = r * rho > 0 ? (r * r + rho * rho - a2) / (2 * r * rho) : -1.0;
      return 2 * r * (cos_top <= -1 ? M_PI : cos_top >= 1 ? 0 : std::acos(cos_top));
    };
    return simpson(ring, r_lo, r_hi, 2000);
  };
  return simpson(slice, lo, hi, 2000);
}

// Cones narrowing and widening, particles inside and outside, balls across the face, at the
// ends and beyond them: the volume against the independent integral, its rate as the centre
// moves against central differences, and a cone of equal radii against the cylinder.
TEST(HinderedVolumes, ConeCutAgainstAnIntegralAndItsRateAgainstDifferences) {
  const double R = 1;
  double worst = 0, worst_rate = 0;
  int reached = 0;
  for (const bool inside : {true, false})
    for (const auto& [r0, r1] : {std::pair{3.0, 6.0}, {6.0, 1.5}, {0.5, 4.0}}) {
      const Wall w = cone_wall(r0, r1, 5.0, inside);
      for (const double z : {-0.7, 0.3, 2.5, 4.6, 5.5})
        for (const double across : {-1.5, -0.6, 0.0, 0.5, 1.3}) {
          // Across the face: a signed offset from the cone's radius at that height, outwards.
          const double c = r0 + (r1 - r0) * std::clamp(z, 0.0, 5.0) / 5.0;
          const double rho = c + across;
          if (rho < 0) continue;
          const Vec3 x{rho * 0.6, rho * 0.8, z};
          const VolumeRate v = cone_cut_volume(w, R, x, {});
          const double reference = cone_cut_by_integral(w, R, x);
          worst = std::max(worst, std::abs(v.volume - reference));
          EXPECT_NEAR(v.volume, reference, 1e-4) << inside << " " << r0 << " " << r1 << " z " << z << " rho " << rho;
          reached += reference > 1e-3;
          // The rate along a direction that moves the centre along the axis and away from it.
          const Vec3 e = Vec3{0.3, 0.5, 0.8} / norm(Vec3{0.3, 0.5, 0.8});
          const double h = 1e-6;
          const double difference =
              (cone_cut_volume(w, R, x + h * e, {}).volume - cone_cut_volume(w, R, x - h * e, {}).volume) / (2 * h);
          const double rate = cone_cut_volume(w, R, x, e).rate;
          worst_rate = std::max(worst_rate, std::abs(rate - difference));
          EXPECT_NEAR(rate, difference, 1e-6) << inside << " " << r0 << " " << r1 << " z " << z << " rho " << rho;
        }
    }
  std::printf("%d balls reaching behind; largest difference from the independent integral %.2g R^3, of the rate from "
              "central differences %.2g R^2\n", reached, worst, worst_rate);
  EXPECT_GT(reached, 60);
  // Equal radii, far from the ends: the cylinder's.
  for (const bool inside : {true, false})
    for (double dist = -0.9; dist < 1.1; dist += 0.17) {
      const double rho = inside ? 4.0 - dist : 4.0 + dist;
      const VolumeRate v = cone_cut_volume(cone_wall(4.0, 4.0, 100.0, inside), R, {rho, 0, 50}, {inside ? -1.0 : 1.0, 0, 0});
      const VolumeSlope cylinder = cylinder_cut_volume(R, 4.0, dist, inside);
      EXPECT_NEAR(v.volume, cylinder.volume, 1e-9) << inside << " " << dist;
      EXPECT_NEAR(v.rate, cylinder.slope, 1e-8) << inside << " " << dist;  // the centre moving away from the surface
    }
}

// Grains of 1 to 2.5 mm in still water with hindered settling beside `wall`, placed at random
// without overlap at place(rng) where clear(x, d) holds: for five grains whose balls reach
// beyond the wall (centres within 0.6 R of it), the room the force field's wall leaves them
// (the ball less cut(x, R), the part behind it) and the solid fraction it finds there,
// against Monte Carlo (40 000 points of the ball's cube, those behind(y) left out).
template <class Place, class Clear, class Behind, class Cut>
void room_against_monte_carlo(const Wall& wall, const Domain& domain, std::size_t n, std::uint64_t seed, Place place,
                              Clear clear, Behind behind, Cut cut) {
  auto [w, model] = testing::make_world({"quartz", kRhoP, 1e7, 0.17}, testing::spec_of("hertz_tsuji", "none", 0.5), 1e-6);
  w.domain = domain;
  w.walls.push_back(wall);
  model.fluid = water(true);
  Random rng(seed);
  while (w.particles.size() < n) {
    const double d = 0.001 + 0.0015 * rng.uniform();
    const Vec3 x = place(rng);
    bool free = clear(x, d);
    for (std::size_t j = 0; j < w.particles.size() && free; ++j) free = norm(x - w.particles.position[j]) > w.particles.radius[j] + d / 2;
    if (free) w.particles.add(static_cast<std::int64_t>(w.particles.size()), 0, d, kRhoP, x, {});
  }
  ForceField forces(model);
  forces.compute(w);
  const Particles& p = w.particles;
  int near_wall = 0;
  for (std::size_t i = 0; i < p.size() && near_wall < 5; ++i) {
    const double R = 3 * p.radius[i], own = 4.0 / 3.0 * M_PI * std::pow(p.radius[i], 3);
    if (wall.touch(p.position[i]).distance > 0.6 * R) continue;  // a grain whose ball reaches well beyond the wall
    ++near_wall;
    int inside = 0, filled = 0;
    for (int k = 0; k < 40000; ++k) {
      const Vec3 y = p.position[i] + R * Vec3{2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
      if (norm(y - p.position[i]) > R || behind(y)) continue;
      ++inside;
      for (std::size_t j = 0; j < p.size(); ++j)
        if (j != i && norm(y - p.position[j]) < p.radius[j]) {
          ++filled;
          break;
        }
    }
    const double ball = 4.0 / 3.0 * M_PI * R * R * R;
    const double room = ball * inside / (M_PI / 6 * 40000);  // the share of the cube's points within the room
    const double share = double(filled) / inside, se = std::sqrt(share * (1 - share) / inside);
    const double expected = suspension_fraction(share * room, 0, room, 0, own).solid_fraction;
    const Crowding c = forces.crowding(i);
    const double exact_room = ball - cut(p.position[i], R);
    std::printf("grain %zu, %.4f m from the wall: room %.4g (Monte Carlo %.4g) m^3; phi %.4f, expected %.4f +- %.4f\n", i,
                wall.touch(p.position[i]).distance, exact_room, room, c.solid_fraction, expected, 5 * se);
    EXPECT_NEAR(room, exact_room, 0.03 * exact_room);
    EXPECT_NEAR(c.solid_fraction, expected, 5 * se + 0.02 * expected);
  }
  EXPECT_EQ(near_wall, 5);
}

// Grains in a hopper (a cone widening upwards) and in a pipe.
TEST(HinderedSettling, TheLocalSolidFractionInAConeAgainstMonteCarlo) {
  const Wall hopper = cone_wall(0.004, 0.014, 0.02, true);  // its radius 0.004 + 0.5 z
  room_against_monte_carlo(
      hopper, {{-0.02, -0.02, -0.005}, {0.02, 0.02, 0.03}, {false, false, false}}, 150, 12,
      [](Random& rng) { return Vec3{(2 * rng.uniform() - 1) * 0.014, (2 * rng.uniform() - 1) * 0.014, 0.002 + 0.016 * rng.uniform()}; },
      // clear of the face (its normal at 27 degrees to the radius)
      [](const Vec3& x, double d) { return std::hypot(x.x, x.y) < 0.004 + 0.5 * x.z - 0.6 * d; },
      [&](const Vec3& y) { return behind_cone(hopper, y); },
      [&](const Vec3& x, double R) { return cone_cut_volume(hopper, R, x, {}).volume; });
}

TEST(HinderedSettling, TheLocalSolidFractionInAPipeAgainstMonteCarlo) {
  const double Rc = 0.008;
  Wall pipe;
  pipe.shape = WallShape::cylinder;
  pipe.axis = {0, 0, 1};
  pipe.radius = Rc;
  room_against_monte_carlo(
      pipe, {{-0.01, -0.01, 0}, {0.01, 0.01, 0.03}, {false, false, false}}, 120, 11,
      [&](Random& rng) { return Vec3{(2 * rng.uniform() - 1) * Rc, (2 * rng.uniform() - 1) * Rc, 0.008 + 0.014 * rng.uniform()}; },
      [&](const Vec3& x, double d) { return std::hypot(x.x, x.y) < Rc - d / 2; },
      [&](const Vec3& y) { return std::hypot(y.x, y.y) > Rc; },
      [&](const Vec3& x, double R) { return cylinder_cut_volume(R, Rc, Rc - std::hypot(x.x, x.y), true).volume; });
}

// A cubic lattice of equal grains falling through still water in a box periodic along all
// three axes (no contacts: the spacing is above the diameter): every grain's ball holds the
// same solid fraction phi, and the grains settle at the Richardson-Zaki speed u_t (1-phi)^n,
// with velocity Verlet and with block steps.
double settled_speed(Integrator integrator, double d, double spacing, double* phi, double* n) {
  auto [w, model] = testing::make_world({"quartz", kRhoP, 1e7, 0.17}, testing::spec_of("hertz_tsuji", "none", 0.5), 1e-5,
                                {0, 0, -kG});
  const int m = 6;
  w.domain = {{0, 0, 0}, {m * spacing, m * spacing, m * spacing}, {true, true, true}};
  model.fluid = water(true);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int c = 0; c < m; ++c)
        w.particles.add(static_cast<std::int64_t>(w.particles.size()), 0, d, kRhoP,
                        {(a + 0.5) * spacing, (b + 0.5) * spacing, (c + 0.5) * spacing}, {});
  ForceField forces(model);
  forces.compute(w);
  *phi = forces.crowding(0).solid_fraction, *n = forces.crowding(0).exponent;
  const double ut = terminal_speed(model.fluid, kRhoP, d, kG);
  const double tau = drag_relaxation_time(model.fluid, d, w.particles.translational_mass[0], ut, forces.crowding(0));
  w.dt = tau / 50;  // 30 relaxation times in 1500 steps
  const std::int64_t steps = 1500;
  if (integrator == Integrator::block_hermite) {
    BlockHermite stepper(BlockStepRules{});
    stepper.start(w, forces);
    for (std::int64_t k = 0; k < steps; ++k) stepper.advance(w, forces);
  } else {
    for (std::int64_t k = 0; k < steps; ++k) advance(integrator, w, testing::evaluation(forces, w));
  }
  double slowest = INFINITY, fastest = 0;
  for (const Vec3& v : w.particles.velocity) slowest = std::min(slowest, -v.z), fastest = std::max(fastest, -v.z);
  EXPECT_LT(fastest - slowest, 1e-9 * fastest);  // every grain alike
  return fastest;
}

TEST(HinderedSettling, ALatticeSettlesAtTheRichardsonZakiSpeed) {
  const Fluid f = water(true);
  for (double d : {2e-4, 2e-3}) {  // Re_t about 3 and 250
    for (Integrator integrator : {Integrator::velocity_verlet, Integrator::block_hermite}) {
      double phi = 0, n = 0;
      const double u = settled_speed(integrator, d, 1.25 * d, &phi, &n);
      const double ut = terminal_speed(f, kRhoP, d, kG), expected = ut * std::pow(1 - phi, n);
      std::printf("d = %g m, %s: phi %.4f, n %.3f, u %.6g m/s, u_t (1-phi)^n %.6g m/s (u_t %.6g)\n", d,
                  integrator_name(integrator), phi, n, u, expected, ut);
      EXPECT_GT(phi, 0.2);
      EXPECT_NEAR(u, expected, 1e-6 * expected);
    }
  }
}

}  // namespace
}  // namespace tsubu
