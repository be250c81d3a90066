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

int RankGrid::cell(int axis, double x) const {
  const double t = (x - domain_.lower[axis]) / domain_.length(axis) * counts_[static_cast<std::size_t>(axis)];
  return static_cast<int>(std::clamp(std::floor(t), 0.0, static_cast<double>(counts_[static_cast<std::size_t>(axis)] - 1)));
}

int RankGrid::owner(const Vec3& x) const { return rank_of({cell(0, x.x), cell(1, x.y), cell(2, x.z)}); }

void RankGrid::near(const Vec3& x, double width, int skip, std::vector<int>& out) const {
  out.clear();
  std::array<std::vector<int>, 3> cells;  // per axis, the cells whose widened interval holds x
  for (int a = 0; a < 3; ++a) {
    const std::size_t k = static_cast<std::size_t>(a);
    const double L = domain_.length(a), size = L / counts_[k];
    for (int c = 0; c < counts_[k]; ++c) {
      const double lo = domain_.lower[a] + c * size - width, hi = domain_.lower[a] + (c + 1) * size + width;
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

double RankGrid::narrowest() const {
  double least = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    if (counts_[static_cast<std::size_t>(a)] > 1) least = std::min(least, domain_.length(a) / counts_[static_cast<std::size_t>(a)]);
  return least;
}

}  // namespace tsubu
