#include "tsubu/ranks/rank_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tsubu {

namespace {

// Every grid of `processes` subdomains (x * y * z = processes), x, then y, ascending.
template <class F>
void for_each_grid(int processes, const F& f) {
  for (int x = 1; x <= processes; ++x)
    for (int y = 1; x * y <= processes; ++y)
      if (processes % (x * y) == 0) f(std::array<int, 3>{x, y, processes / (x * y)});
}

}  // namespace

RankGrid::RankGrid(const Domain& domain, int processes, std::array<int, 3> counts) : domain_(domain) {
  if (!fits(counts, processes))
    throw std::invalid_argument("the grid of subdomains " + std::to_string(counts[0]) + " x " + std::to_string(counts[1]) +
                                " x " + std::to_string(counts[2]) + " does not match " + std::to_string(processes) +
                                " processes");
  double least = std::numeric_limits<double>::infinity();
  for_each_grid(processes, [&](const std::array<int, 3>& c) {
    if (!matches(c, counts)) return;
    const double a = domain.length(0) / c[0], b = domain.length(1) / c[1], h = domain.length(2) / c[2];
    const double surface = a * b + b * h + h * a;
    if (surface < least * (1 - 1e-12)) least = surface, counts_ = c;
  });
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c <= counts_[static_cast<std::size_t>(a)]; ++c)
      cuts_[static_cast<std::size_t>(a)].push_back(bin_edge(a, c * kBinsPerSlab));
}

bool RankGrid::matches(const std::array<int, 3>& grid, const std::array<int, 3>& counts) {
  for (std::size_t a = 0; a < 3; ++a)
    if (counts[a] != 0 && counts[a] != grid[a]) return false;
  return true;
}

bool RankGrid::fits(const std::array<int, 3>& counts, int processes) {
  bool any = false;
  for_each_grid(processes, [&](const std::array<int, 3>& c) { any = any || matches(c, counts); });
  return any;
}

double RankGrid::bin_edge(int axis, int edge) const {
  return edge == bins(axis) ? domain_.upper[axis] : domain_.lower[axis] + domain_.length(axis) * edge / bins(axis);
}

int RankGrid::bin(int axis, double x) const {
  const double t = (x - domain_.lower[axis]) / domain_.length(axis) * bins(axis);
  return static_cast<int>(std::clamp(std::floor(t), 0.0, static_cast<double>(bins(axis) - 1)));
}

int RankGrid::cell(int axis, double x) const {
  // The inner cuts at or below x; a position on a cut belongs to the slab above it.
  const std::vector<double>& c = cuts_[static_cast<std::size_t>(axis)];
  return static_cast<int>(std::upper_bound(c.begin() + 1, c.end() - 1, x) - (c.begin() + 1));
}

void RankGrid::balance(const std::array<std::vector<std::int64_t>, 3>& work) {
  for (int a = 0; a < 3; ++a) {
    const std::size_t k = static_cast<std::size_t>(a);
    const std::int64_t slabs = counts_[k];
    const std::vector<std::int64_t>& w = work[k];
    std::int64_t total = 0;
    for (std::int64_t v : w) total += v;
    if (slabs == 1 || total == 0) continue;
    // Cut s at the first bin edge below which lies s / slabs of the work, at least one bin
    // above the cut before it and leaving a bin for each slab above.
    std::int64_t below = 0;
    int edge = 0;
    for (std::int64_t s = 1; s < slabs; ++s) {
      const int lowest = edge + 1, highest = bins(a) - static_cast<int>(slabs - s);
      while (edge < lowest || (edge < highest && below * slabs < total * s)) below += w[static_cast<std::size_t>(edge++)];
      cuts_[k][static_cast<std::size_t>(s)] = bin_edge(a, edge);
    }
  }
}

int RankGrid::owner(const Vec3& x) const { return rank_of({cell(0, x.x), cell(1, x.y), cell(2, x.z)}); }

void RankGrid::near(const Vec3& x, double width, int skip, std::vector<int>& out) const {
  out.clear();
  std::array<std::vector<int>, 3> cells;  // per axis, the cells whose widened interval holds x
  for (int a = 0; a < 3; ++a) {
    const std::size_t k = static_cast<std::size_t>(a);
    const double L = domain_.length(a);
    for (int c = 0; c < counts_[k]; ++c) {
      const double lo = cuts_[k][static_cast<std::size_t>(c)] - width, hi = cuts_[k][static_cast<std::size_t>(c) + 1] + width;
      bool in = x[a] >= lo && x[a] <= hi;
      if (domain_.periodic[k]) in = in || (x[a] + L >= lo && x[a] + L <= hi) || (x[a] - L >= lo && x[a] - L <= hi);
      else if (c == 0) in = in || x[a] < lo;  // outside a closed side
      else if (c == counts_[k] - 1) in = in || x[a] > hi;
      if (in) cells[k].push_back(c);
    }
  }
  for (int cz : cells[2])
    for (int cy : cells[1])
      for (int cx : cells[0])
        if (const int r = rank_of({cx, cy, cz}); r != skip) out.push_back(r);
  std::sort(out.begin(), out.end());
}

}  // namespace tsubu
