#include "tsubu/fluid/crowding.hpp"

#include <algorithm>
#include <cmath>

#include "tsubu/core/parallel.hpp"

namespace tsubu {

VolumeSlope cap_volume(double R, double dist) {
  if (dist >= R) return {};
  if (dist <= -R) return {ball_volume(R), 0};
  const double h = R - dist;
  return {M_PI / 3 * h * h * (3 * R - h), -M_PI * (R * R - dist * dist)};
}

SuspensionFraction suspension_fraction(double solid, double solid_rate, double room, double room_rate, double own) {
  if (solid == 0) return {0, 0};  // a lone grain
  // g(phi) = phi room - solid - own (1 - S(phi)) rises from <= 0 at solid/room to >= 0 at
  // (solid + own)/room while room > 8 own (|S'| <= 8): Newton's method from the low end
  // (2 to 4 steps), kept inside the bracket.
  auto structure = [](double phi, double* slope) {
    const double a = 1 - phi, c = 1 / (1 + 2 * phi), a3c2 = a * a * a * c * c;
    *slope = -4 * a3c2 * c * (2 + phi);
    return a3c2 * a;
  };
  double lo = solid / room, hi = (solid + own) / room, phi = lo, slope = 0;
  for (int it = 0; it < 50; ++it) {
    const double g = phi * room - solid - own * (1 - structure(phi, &slope));
    if (g == 0) break;
    (g < 0 ? lo : hi) = phi;
    double next = phi - g / (room + own * slope);
    if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);
    // Quadratic convergence: after a step below 1e-8 the error is below |g''/2g'| 1e-16, and
    // g''/2g' = own S''/2(room + own S') is below 5 for rooms of at least 12 own (S'' <= 68;
    // a ball of 2.5 radii or more, less the cap behind a wall the grain touches).
    const bool done = std::abs(next - phi) <= 1e-8;
    phi = next;
    if (done) break;
  }
  structure(phi, &slope);
  return {phi, (solid_rate - phi * room_rate) / (room + own * slope)};
}

void CrowdList::build(const World& world, const Fluid& fluid, double g, const std::vector<Pair>& found) {
  const Particles& p = world.particles;
  const std::size_t n = p.size();
  start_.assign(n + 1, 0);
  for (const Pair& q : found) ++start_[q.i + 1], ++start_[q.j + 1];
  for (std::size_t i = 0; i < n; ++i) start_[i + 1] += start_[i];
  neighbour_.resize(start_[n]);
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (const Pair& q : found) neighbour_[fill[q.j]++] = q.i;
  for (const Pair& q : found) neighbour_[fill[q.i]++] = q.j;
  // Each grain's neighbours in the order of their ids: the sums over them then have the
  // same bits however the particles are numbered (a spatial sort, processes).
  parallel_for(n, [&](std::size_t i) {
    std::sort(neighbour_.begin() + start_[i], neighbour_.begin() + start_[i + 1],
              [&](std::uint32_t a, std::uint32_t b) { return p.id[a] < p.id[b]; });
  });
  exponent_.resize(n);
  ball_ratio_ = fluid.hindered_ball_ratio;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = 2 * p.radius[i], rho = p.mass[i] / (M_PI * d * d * d / 6);
    exponent_[i] = richardson_zaki_exponent(terminal_speed(fluid, rho, d, g) * d / fluid.viscosity);
  }
}

}  // namespace tsubu
