#include "tsubu/fluid/crowding.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "tsubu/core/parallel.hpp"

namespace tsubu {

VolumeSlope cap_volume(double R, double dist) {
  if (dist >= R) return {};
  if (dist <= -R) return {ball_volume(R), 0};
  const double h = R - dist;
  return {M_PI / 3 * h * h * (3 * R - h), -M_PI * (R * R - dist * dist)};
}

namespace {

// Circles of radii a and c whose centres are d apart: their common area; the half-angle, at
// a's centre, of a's arc inside c (pi: all of it; its area's derivative with respect to a is
// 2 a alpha); and half their common chord (the derivative with respect to d is minus the chord).
struct LensParts {
  double area, alpha, half_chord;
};
LensParts circle_lens_parts(double a, double c, double d) {
  if (d >= a + c) return {0, 0, 0};
  if (d <= c - a) return {M_PI * a * a, M_PI, 0};
  if (d <= a - c) return {M_PI * c * c, 0, 0};
  const double k = std::sqrt((-d + a + c) * (d + a - c) * (d - a + c) * (d + a + c));  // 4 x the triangle's area
  const double alpha = std::acos(std::clamp((d * d + a * a - c * c) / (2 * d * a), -1.0, 1.0));
  const double gamma = std::acos(std::clamp((d * d + c * c - a * a) / (2 * d * c), -1.0, 1.0));
  return {a * a * alpha + c * c * gamma - 0.5 * k, alpha, 0.5 * k / d};
}

// Gauss-Legendre nodes and weights on [0, 1], n points (Newton's method on P_n).
template <int N>
struct GaussLegendre {
  std::array<double, N> x{}, w{};
  GaussLegendre() {
    for (int i = 0; i < N; ++i) {
      double t = std::cos(M_PI * (i + 0.75) / (N + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = t;
        for (int k = 2; k <= N; ++k) {
          const double p2 = ((2 * k - 1) * t * p1 - (k - 1) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = N * (t * p1 - p0) / (t * t - 1);
        const double step = p1 / dp;
        t -= step;
        if (std::abs(step) < 1e-16) break;
      }
      x[static_cast<std::size_t>(i)] = 0.5 * (1 - t);
      w[static_cast<std::size_t>(i)] = 1 / ((1 - t * t) * dp * dp);  // 2/((1-t^2) P'^2), halved for [0, 1]
    }
  }
};

}  // namespace

VolumeSlope cylinder_cut_volume(double R, double cylinder_radius, double dist, bool inside) {
  if (dist >= R) return {};
  if (dist <= -R) return {ball_volume(R), 0};
  const double rho = inside ? cylinder_radius - dist : cylinder_radius + dist;  // the centre from the axis
  // A slice at height z across the axis is a disk of radius a = sqrt(R^2 - z^2) centred rho
  // from the axis; it crosses the surface where a > |dist|, i.e. |z| < z*. Behind the surface
  // it has (inside) its area less the lens with the cylinder's circle, or (outside) the lens.
  // The lens's derivative with respect to rho is minus the chord; rho moves as -dist
  // (inside) or +dist (outside), so the volume's derivative is minus the chords' integral
  // both ways (and zero at |z| = z*, where the slice touches the circle).
  const double z_star = std::sqrt(std::max(R * R - dist * dist, 0.0));
  static const GaussLegendre<24> rule;
  double volume = 0, slope = 0;
  // Over t in [from, to] (z = z* sin t, dz = z* cos t dt); t = from + (to - from) u^2 where
  // the chords rise from zero as a square root at `from` (smooth in u).
  auto add = [&](double from, double to, bool root_at_from) {
    for (std::size_t k = 0; k < rule.x.size(); ++k) {
      const double u = rule.x[k];
      const double t = from + (to - from) * (root_at_from ? u * u : u);
      const double dt = (to - from) * (root_at_from ? 2 * u : 1.0) * rule.w[k];
      const double z = z_star * std::sin(t), dz = z_star * std::cos(t) * dt;
      const double a = std::sqrt(std::max(R * R - z * z, 0.0));
      const LensParts lens = circle_lens_parts(a, cylinder_radius, rho);
      volume += (inside ? M_PI * a * a - lens.area : lens.area) * dz;
      slope -= 2 * lens.half_chord * dz;
    }
  };
  // Slices wider than rho + Rc hold the cylinder's whole circle (a ball wider than a narrow
  // pipe): a kink of the integrand, where the quadrature is split.
  const double holds = rho + cylinder_radius;
  if (holds < R && holds > std::abs(dist)) {
    const double split = std::asin(std::min(1.0, std::sqrt(R * R - holds * holds) / z_star));
    add(0, split, false);  // slices holding the circle: their chords are zero
    add(split, 0.5 * M_PI, true);
  } else {
    add(0, 0.5 * M_PI, false);
  }
  // A centre behind the surface (dist < 0; no run gets there, its overlap stops it first):
  // the slices |z| > z* lie behind whole. Their volume's derivative cancels the one of the
  // integral's moving ends, where the slice is behind whole too.
  const double whole = dist < 0 ? 2 * M_PI * (R * R * (R - z_star) - (R * R * R - z_star * z_star * z_star) / 3) : 0.0;
  return {2 * volume + whole, 2 * slope};  // both halves, z < 0 and z > 0
}

namespace {

// The distance from (s, rho) in a half-plane through the axis to the segment from (s0, r0)
// to (s1, r1).
double to_segment(double s, double rho, double s0, double r0, double s1, double r1) {
  const double ds = s1 - s0, dr = r1 - r0;
  const double t = std::clamp(((s - s0) * ds + (rho - r0) * dr) / (ds * ds + dr * dr), 0.0, 1.0);
  return std::hypot(s - s0 - t * ds, rho - r0 - t * dr);
}

}  // namespace

VolumeRate cone_cut_volume(const Wall& cone, double R, const Vec3& x, const Vec3& v) {
  // In a half-plane through the axis the region behind is, with c(s) = radius + k s the
  // cone's radius at s along the axis: 0 <= s <= length and rho >= c(s) for particles inside
  // (rho <= c(s) outside). Out of the ball's reach when its centre is farther from it than R.
  const double L = cone.length, k = (cone.end_radius - cone.radius) / L;
  const Vec3 rel = x - cone.point;
  const double s_c = dot(rel, cone.axis);
  const Vec3 off = rel - s_c * cone.axis;
  const double rho = norm(off);
  const double ds = dot(v, cone.axis), drho = rho > 0 ? dot(off, v) / rho : 0.0;  // the centre's rates
  const double c_c = cone.radius + k * s_c;
  const bool within = s_c >= 0 && s_c <= L && (cone.inside ? rho >= c_c : rho <= c_c);
  if (!within) {
    double reach = to_segment(s_c, rho, 0, cone.radius, L, cone.end_radius);  // the face
    // The ends: from the rims outwards (inside), or inwards to the axis (outside).
    const double far = cone.inside ? std::max(rho, std::max(cone.radius, cone.end_radius)) + R : 0.0;
    reach = std::min({reach, to_segment(s_c, rho, 0, cone.radius, 0, far), to_segment(s_c, rho, L, cone.end_radius, L, far)});
    if (reach >= R) return {};
  }
  // Slices at s = s_c + u: a disk of radius a(u) = sqrt(R^2 - u^2) whose centre is rho from
  // the axis, and the cone's circle of radius c_c + k u.
  const double lo = std::max(-R, -s_c), hi = std::min(R, L - s_c);
  if (!(lo < hi)) return {};
  std::array<double, 6> cuts{};  // the kinks inside (lo, hi): a = |c - rho| and a = c + rho
  std::size_t n_cuts = 0;
  for (const double e : {c_c - rho, c_c + rho}) {
    // R^2 - u^2 = (e + k u)^2: (1 + k^2) u^2 + 2 e k u + e^2 - R^2 = 0.
    const double disc = (1 + k * k) * R * R - e * e;
    if (disc <= 0) continue;
    for (const double sign : {-1.0, 1.0}) {
      const double u = (-e * k + sign * std::sqrt(disc)) / (1 + k * k);
      if (u > lo && u < hi) cuts[n_cuts++] = u;
    }
  }
  std::sort(cuts.begin(), cuts.begin() + static_cast<std::ptrdiff_t>(n_cuts));
  static const GaussLegendre<24> rule;
  double volume = 0, rate = 0;
  auto slice = [&](double u, double du) {
    const double a = std::sqrt(std::max(R * R - u * u, 0.0));
    const LensParts lens = circle_lens_parts(a, c_c + k * u, rho);
    // d(a^2)/dt = 2 u ds (at a fixed height), d(lens)/da = 2 a alpha, d(lens)/drho = -2 h.
    if (cone.inside) {
      volume += (M_PI * a * a - lens.area) * du;
      rate += (2 * (M_PI - lens.alpha) * u * ds + 2 * lens.half_chord * drho) * du;
    } else {
      volume += lens.area * du;
      rate += (2 * lens.alpha * u * ds - 2 * lens.half_chord * drho) * du;
    }
  };
  // Each piece from p to q in two halves, each mapped as u = end + (mid - end) w^2: square
  // roots at the ends (of the areas at a kink, of a at u = +-R) become smooth in w.
  auto piece = [&](double p, double q) {
    const double mid = 0.5 * (p + q);
    for (std::size_t i = 0; i < rule.x.size(); ++i) {
      const double w = rule.x[i], weight = 2 * w * rule.w[i];
      slice(p + (mid - p) * w * w, (mid - p) * weight);
      slice(q - (q - mid) * w * w, (q - mid) * weight);
    }
  };
  double from = lo;
  for (std::size_t i = 0; i < n_cuts; ++i) piece(from, cuts[i]), from = cuts[i];
  piece(from, hi);
  return {volume, rate};
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
