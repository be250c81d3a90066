#include "tsubu/analysis/deposit.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/core/exact_sum.hpp"
#include "tsubu/core/random.hpp"
#include "tsubu/core/stop_signal.hpp"
#include "tsubu/search/sphere_grid.hpp"

namespace tsubu {

double solid_volume(const Packing& p, double a, double b) {
  ExactSum solid;
  for (std::size_t i = 0; i < p.position.size(); ++i) solid += sphere_slab_volume(p.position[i].z, p.radius[i], a, b);
  return solid.value();
}

double solid_fraction(const Packing& p, double a, double b) { return solid_volume(p, a, b) / (p.base_area() * (b - a)); }

long grains_in_slab(std::span<const Vec3> position, double a, double b) {
  return std::count_if(position.begin(), position.end(), [&](const Vec3& x) { return x.z > a && x.z < b; });
}

double deposit_height(const Packing& p, const SliceRule& rule) {
  for (int k = rule.slices; k >= 1; --k)
    if (solid_fraction(p, rule.floor, rule.floor + k * rule.slice) > rule.threshold) return k * rule.slice;
  return 0;
}

double surface_height(const Packing& p, const SurfaceRule& rule) {
  constexpr int steps = 8;  // per window
  const double step = rule.window / steps;
  const int bins = std::max(steps, static_cast<int>(std::ceil((rule.top - rule.floor) / step)));
  std::vector<ExactSum> bin_sums(static_cast<std::size_t>(bins));  // exact volume in each bin
  // Bin indices clamped as doubles first: a grain far outside the box casts no huge value.
  auto bin = [&](double height) { return static_cast<int>(std::clamp(std::floor((height - rule.floor) / step), -1.0, double(bins))); };
  for (std::size_t i = 0; i < p.position.size(); ++i) {
    const double z = p.position[i].z, r = p.radius[i];
    const int first = std::max(0, bin(z - r)), last = std::min(bins - 1, bin(z + r));
    for (int b = first; b <= last; ++b)
      bin_sums[static_cast<std::size_t>(b)] += sphere_slab_volume(z, r, rule.floor + b * step, rule.floor + (b + 1) * step);
  }
  std::vector<double> solid;
  for (const ExactSum& s : bin_sums) solid.push_back(s.value());
  const double volume = p.base_area() * rule.window;
  auto phi = [&](int j) {  // the window [floor + j step, floor + j step + window]
    double sum = 0;
    for (int b = j; b < j + steps; ++b) sum += solid[static_cast<std::size_t>(b)];
    return sum / volume;
  };
  // The reference: the largest windowed solid fraction met so far, but at least
  // kDepositSolidFraction, so that a sparse first layer or a falling cloud (looser) is not
  // taken for the deposit's bulk.
  double largest = std::max(phi(0), kDepositSolidFraction), previous = phi(0);
  // A first window less than half full: the floor's layer is forming; its height grows from 0
  // with its solid, up to the centre of that window once it is half full.
  if (previous < 0.5 * largest) return 0.5 * rule.window * previous / (0.5 * largest);
  int j = 1;
  for (; j + steps <= bins; ++j) {
    const double now = phi(j);
    if (now < 0.5 * largest) {  // between the centres of windows j - 1 and j
      const double centre = rule.window / 2 + (j - 1) * step;
      return centre + step * (previous - 0.5 * largest) / (previous - now);
    }
    largest = std::max(largest, now);
    previous = now;
  }
  return rule.window / 2 + (j - 1) * step;  // the deposit fills the box
}

PorosityEstimate porosity_monte_carlo(const Packing& p, double a, double b, long points, std::uint64_t seed) {
  const Domain& d = p.domain;
  double r_max = 0;
  for (std::size_t i = 0; i < p.position.size(); ++i)
    if (sphere_slab_volume(p.position[i].z, p.radius[i], a, b) > 0) r_max = std::max(r_max, p.radius[i]);
  PorosityEstimate e;
  e.points = points;
  if (r_max == 0) return e;
  const Vec3 lower{d.lower.x, d.lower.y, a - r_max}, upper{d.upper.x, d.upper.y, b + r_max};
  SphereGrid grains(d, lower, upper, {d.periodic[0], d.periodic[1], false}, r_max);
  for (std::size_t i = 0; i < p.position.size(); ++i)
    if (sphere_slab_volume(p.position[i].z, p.radius[i], a, b) > 0) grains.add(p.position[i], p.radius[i]);
  Random rng(seed);
  long solid = 0;
  for (long n = 0; n < points; ++n) {
    if (n % 65536 == 65535) poll_stop();
    const Vec3 x{rng.uniform(d.lower.x, d.upper.x), rng.uniform(d.lower.y, d.upper.y), rng.uniform(a, b)};
    solid += grains.overlaps(x, 0);
  }
  e.porosity = 1 - static_cast<double>(solid) / static_cast<double>(points);
  e.standard_error = std::sqrt(e.porosity * (1 - e.porosity) / static_cast<double>(points));
  return e;
}

Coordination coordination_numbers(std::span<const Vec3> position, std::span<const int> pair_contacts, double a, double b) {
  long sum = 0, sum_2 = 0, sum_4 = 0;
  Coordination c;
  for (std::size_t i = 0; i < position.size(); ++i) {
    if (!(position[i].z > a && position[i].z < b)) continue;
    const int z = pair_contacts[i];
    ++c.grains;
    sum += z;
    if (z < 2) ++c.rattlers_2;
    else sum_2 += z;
    if (z < 4) ++c.rattlers_4;
    else sum_4 += z;
  }
  auto mean = [](long contacts, long grains) { return grains ? static_cast<double>(contacts) / static_cast<double>(grains) : 0.0; };
  c.all = mean(sum, c.grains);
  c.without_rattlers_2 = mean(sum_2, c.grains - c.rattlers_2);
  c.without_rattlers_4 = mean(sum_4, c.grains - c.rattlers_4);
  return c;
}

double small_grain_share(const Packing& p, double a, double b, double small_diameter) {
  ExactSum small, all;
  for (std::size_t i = 0; i < p.position.size(); ++i) {
    const double v = sphere_slab_volume(p.position[i].z, p.radius[i], a, b);
    all += v;
    if (2 * p.radius[i] < small_diameter) small += v;
  }
  return all.value() > 0 ? small.value() / all.value() : 0.0;
}

}  // namespace tsubu
