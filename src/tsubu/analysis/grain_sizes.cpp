#include "tsubu/analysis/grain_sizes.hpp"

#include <algorithm>
#include <limits>

namespace tsubu {

MassPercentiles mass_percentiles(std::vector<SizedGrain> grains) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  if (grains.empty()) return {none, none, none};
  // By size, and equal sizes by mass: one order whatever the grains' numbering, so that the
  // running sums below have the same bits.
  std::sort(grains.begin(), grains.end(), [](const SizedGrain& a, const SizedGrain& b) {
    return a.diameter != b.diameter ? a.diameter < b.diameter : a.mass < b.mass;
  });
  double total = 0;
  for (const SizedGrain& g : grains) total += g.mass;
  const double q[3] = {0.1, 0.5, 0.9};
  double d[3] = {grains.back().diameter, grains.back().diameter, grains.back().diameter};
  double below = 0;
  int next = 0;
  for (const SizedGrain& g : grains) {
    below += g.mass;
    while (next < 3 && below >= q[next] * total) d[next++] = g.diameter;
    if (next == 3) break;
  }
  return {d[0], d[1], d[2]};
}

std::vector<SourceSizes> source_sizes(const World& w) {
  std::vector<std::vector<SizedGrain>> grains(w.source_ids.size());
  const Particles& p = w.particles;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t k = 0; k < w.source_ids.size(); ++k)
      if (p.id[i] >= w.source_ids[k].first && p.id[i] < w.source_ids[k].second) grains[k].push_back({2 * p.radius[i], p.mass[i]});
  std::vector<SourceSizes> out;
  for (const std::vector<SizedGrain>& g : grains) out.push_back({static_cast<long>(g.size()), mass_percentiles(g)});
  return out;
}

}  // namespace tsubu
