// The solid fraction around each grain, for hindered settling (Fluid::hindered): from the
// volume that the other grains fill in a ball of radius R_i = c r_i (c =
// Fluid::hindered_ball_ratio) around grain i, less the part behind any wall (exact
// sphere-sphere intersection volumes; a plane's cap; beyond a cylinder or a cone, by quadrature),
// corrected for the correlation hole around a grain (docs/engine.md, "Hindered settling").
// A lone grain sees 0. The rate follows from the derivatives of the same volumes, so the
// hindered drag's jerk is exact.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tsubu/fluid/fluid.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// A volume and its derivative with respect to a distance.
struct VolumeSlope {
  double volume = 0, slope = 0;
};

// The volume of a ball of radius r, m^3.
inline double ball_volume(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }

// The intersection of balls of radii R and r whose centres are `dist` apart, m^3, and its
// derivative with respect to dist: -pi a^2, a the radius of the circle where the spheres
// meet (zero when apart and when one lies inside the other, so the volume is C^1 in dist).
inline VolumeSlope lens_volume(double R, double r, double dist) {
  if (dist >= R + r) return {};
  const double small = std::min(R, r);
  if (dist <= std::abs(R - r)) return {ball_volume(small), 0};
  // The circle where the spheres meet lies at x from the ball's centre; the lens is a cap of
  // each sphere: heights R - x and r - (dist - x).
  const double x = (dist * dist + R * R - r * r) / (2 * dist);
  const double h1 = R - x, h2 = r - (dist - x);
  const double volume = M_PI / 3 * (h1 * h1 * (3 * R - h1) + h2 * h2 * (3 * r - h2));
  return {volume, -M_PI * (R * R - x * x)};
}

// The part of a ball of radius R beyond a plane at signed distance `dist` from its centre
// (positive: the centre is in front), the cap of height R - dist, m^3, and its derivative
// with respect to dist (-pi a^2, a^2 = R^2 - dist^2).
VolumeSlope cap_volume(double R, double dist);

// The part of a ball of radius R beyond the surface of an infinite cylinder of radius
// `cylinder_radius` (outside it for `inside`, the particles' side being inside; inside it
// otherwise), the ball's centre at distance `dist` from the surface on the particles' side,
// m^3, and its derivative with respect to dist. By slices across the axis: each a disk of the
// ball meeting the cylinder's circle (circle-circle areas, exact), summed by Gauss-Legendre
// quadrature over z = z* sin(t) (z* the half height of the slices that cross the surface),
// whose integrands are smooth in t; split where a slice of a ball wider than a narrow pipe
// holds its whole circle. Against an independent integral within that integral's accuracy
// (2e-5 R^3); the derivative against central differences to 1e-6 R^2
// (tests/unit/test_hindered.cpp).
VolumeSlope cylinder_cut_volume(double R, double cylinder_radius, double dist, bool inside);

// The part of a ball of radius R centred at x behind a cone's face (Wall, shape cone): beyond
// its surface on the far side from the particles, between the planes of its two ends, m^3,
// and that volume's rate as the centre moves at v relative to the cone, m^3/s. By slices
// across the axis, each a disk of the ball meeting the cone's circle there (circle-circle
// areas, exact), summed by Gauss-Legendre quadrature between the heights where the integrand
// has kinks (a slice's disk touching the circle, holding it, the cone's ends), each piece
// mapped so that the square roots at its ends are smooth; the rate from the derivatives of
// the slices' areas (their arcs and chords). Zero where the ball does not reach that region.
struct VolumeRate {
  double volume = 0, rate = 0;
};
VolumeRate cone_cut_volume(const Wall& cone, double R, const Vec3& x, const Vec3& v);

// The part of a ball of radius R around a grain at distance `dist` from wall w on its side,
// which lies behind the wall: a plane's cap, or beyond a cylinder's surface (cones:
// cone_cut_volume).
inline VolumeSlope volume_behind(const Wall& w, double R, double dist) {
  return w.shape == WallShape::cylinder ? cylinder_cut_volume(R, w.radius, dist, w.inside) : cap_volume(R, dist);
}

// Where a grain is and how it moves, as CrowdList::of reads it.
struct PointMotion {
  Vec3 x, v;
};

// The solid fraction phi of a homogeneous suspension, and its rate, from what a ball around
// one of its grains holds: the other grains' volume `solid` in the ball's `room` (m^3) and
// their rates, and the grain's own volume. Around a grain the others are held off (the
// correlation hole): on average the ball holds phi room - (1 - S) v of them, S the structure
// factor at zero wave number, (1-phi)^4/(1+2 phi)^2 for hard spheres (Percus-Yevick), so phi
// solves phi room = solid + (1 - S(phi)) v. A lone grain gets 0. Needs room > 12 v (a ball of
// at least 2.5 radii, Fluid::hindered_ball_ratio).
struct SuspensionFraction {
  double solid_fraction, rate;
};
SuspensionFraction suspension_fraction(double solid, double solid_rate, double room, double room_rate, double own);

// Each grain's neighbours within reach of its ball, and its Richardson-Zaki exponent; built
// with the contact lists and valid as long as they are.
class CrowdList {
 public:
  // From `found` (pairs i < j sorted by (i, j), within the balls' reach) over the particles
  // of `world` in `fluid` under gravity g (m/s^2); the exponents from each grain's terminal
  // Reynolds number.
  void build(const World& world, const Fluid& fluid, double g, const std::vector<Pair>& found);
  // The ball radii to search with: c r_i + reach_i, where probe_radius = r_i + reach_i.
  static double probe_radius(const Fluid& fluid, double radius, double probe_radius) {
    return probe_radius + (fluid.hindered_ball_ratio - 1) * radius;
  }
  bool empty() const { return start_.empty(); }

  // The solid fraction around grain i and its rate (suspension_fraction; the rate only with
  // `Rates`, zero without), positions and velocities from at(j) (a PointMotion).
  template <bool Rates, class At>
  Crowding of(const World& world, std::size_t i, const At& at) const {
    const Particles& p = world.particles;
    const PointMotion self = at(i);
    const double r = p.radius[i], R = ball_ratio_ * r;
    double solid = 0, solid_rate = 0;  // of the other grains in the ball
    for (std::uint32_t k = start_[i]; k < start_[i + 1]; ++k) {
      const std::uint32_t j = neighbour_[k];
      const PointMotion other = at(j);
      const Vec3 sep = world.domain.separation(other.x, self.x);
      const double reach = R + p.radius[j], dist2 = norm2(sep);
      if (dist2 >= reach * reach) continue;
      const double dist = std::sqrt(dist2);
      const VolumeSlope lens = lens_volume(R, p.radius[j], dist);
      solid += lens.volume;
      if (Rates && lens.slope != 0) solid_rate += lens.slope * dot(sep, other.v - self.v) / dist;
    }
    double room = ball_volume(R), room_rate = 0;
    for (const Wall& w : world.walls) {
      if (w.shape == WallShape::cone) {
        const VolumeRate behind = cone_cut_volume(w, R, self.x, self.v - w.velocity);
        room -= behind.volume;
        if (Rates) room_rate -= behind.rate;
        continue;
      }
      const WallTouch touch = w.touch(self.x);  // a plane or a cylinder (the scenario refuses holes and meshes here)
      const double dist = touch.distance;
      if (dist >= R) continue;
      const VolumeSlope behind = volume_behind(w, R, dist);
      room -= behind.volume;
      if (Rates) room_rate -= behind.slope * dot(self.v - w.velocity, touch.normal);
    }
    const SuspensionFraction phi = suspension_fraction(solid, solid_rate, room, room_rate, ball_volume(r));
    return {phi.solid_fraction, phi.rate, exponent_[i]};
  }

 private:
  std::vector<std::uint32_t> start_;      // per particle + 1, offsets into neighbour_
  std::vector<std::uint32_t> neighbour_;  // each particle's neighbours in ascending order
  std::vector<double> exponent_;          // Richardson-Zaki n per particle
  double ball_ratio_ = 0;                 // Fluid::hindered_ball_ratio
};

}  // namespace tsubu
