// Multi-level grid (docs/engine.md, "Contact search"); see pair_search.hpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "tsubu/core/parallel.hpp"
#include "tsubu/search/pair_search.hpp"

namespace tsubu {

namespace {

// Cells covered along one axis by [x - r, x + r]: first cell and count, before wrapping or
// clipping. A slack of 1e-9 cell absorbs the round-off between a position and its periodic
// image; candidates are filtered by the exact distance test, so extra cells cost time only.
inline void cover(double x, double r, double origin, double length, int& lo, int& hi) {
  lo = static_cast<int>(std::floor((x - r - origin) / length - 1e-9));
  hi = static_cast<int>(std::floor((x + r - origin) / length + 1e-9));
}

// Distinct cell indices of [lo, hi] along an axis of n cells: wrapped or clipped.
inline int axis_cells(int lo, int hi, int n, bool periodic, int* out) {
  int count = 0;
  if (periodic) {
    if (hi - lo + 1 >= n) {
      for (int c = 0; c < n; ++c) out[count++] = c;
    } else {
      for (int c = lo; c <= hi; ++c) out[count++] = ((c % n) + n) % n;
    }
  } else {
    for (int c = std::max(lo, 0); c <= std::min(hi, n - 1); ++c) out[count++] = c;
  }
  return count;
}

}  // namespace

double MultiLevelGrid::top_level_size(double base_length, double d_max) {
  int e;
  std::frexp(base_length / d_max, &e);  // base/d_max in [2^(e-1), 2^e)
  double l1 = std::ldexp(base_length, -(e - 1));
  // Exact powers of two of the base length: settle the boundary cases by comparison.
  while (l1 < d_max) l1 *= 2;
  while (l1 * 0.5 >= d_max) l1 *= 0.5;
  return l1;
}

int MultiLevelGrid::level_for(double d, double l1, int levels) {
  int k = 1;
  while (k < levels && d <= std::ldexp(l1, -k)) ++k;  // d <= l_{k+1}: finer
  return k;
}

void MultiLevelGrid::span(const Particles& p, const Domain& domain) { grid_span(p, domain, origin_, extent_); }

void MultiLevelGrid::cell_dims(double size, std::size_t count, int* cells, double* length) const {
  grid_cells(extent_, size, count, cells, length);
}

std::vector<MultiLevelGrid::Estimate> MultiLevelGrid::estimate(const Particles& p, const Domain& domain,
                                                               double margin) const {
  std::vector<Estimate> result;
  const std::size_t n = p.size();
  if (n == 0) return result;
  MultiLevelGrid geometry;  // the span, without touching this grid's state
  geometry.span(p, domain);
  const double d_max = 2.0 * *std::max_element(p.radius.begin(), p.radius.end());
  const double l1 = top_level_size(domain.length(0), d_max);
  // Counts and largest radius per level with no limit on the number of levels.
  std::vector<std::size_t> count(kMaxLevels + 1, 0);
  std::vector<double> r_max(kMaxLevels + 1, 0.0);
  int finest = 1;
  for (std::size_t i = 0; i < n; ++i) {
    const int k = level_for(2 * p.radius[i], l1, kMaxLevels);
    ++count[static_cast<std::size_t>(k)];
    r_max[static_cast<std::size_t>(k)] = std::max(r_max[static_cast<std::size_t>(k)], p.radius[i]);
    finest = std::max(finest, k);
  }
  // A sample of at most 4096 particles (every stride-th) stands for all in the search term.
  const std::size_t stride = std::max<std::size_t>(1, n / 4096);
  const double weight = static_cast<double>(stride) * static_cast<double>(n) /
                        static_cast<double>(stride * ((n + stride - 1) / stride));
  for (int m = 1; m <= finest; ++m) {
    Estimate e;
    e.levels = m;
    struct Lv {
      std::size_t count = 0;
      double r_max = 0;
      int cells[3];
      double length[3];
    };
    std::vector<Lv> lv(static_cast<std::size_t>(m) + 1);
    for (int k = 1; k <= finest; ++k) {
      Lv& l = lv[static_cast<std::size_t>(std::min(k, m))];
      l.count += count[static_cast<std::size_t>(k)];
      l.r_max = std::max(l.r_max, r_max[static_cast<std::size_t>(k)]);
    }
    for (int k = 1; k <= m; ++k) {
      Lv& l = lv[static_cast<std::size_t>(k)];
      if (l.count == 0) continue;
      geometry.cell_dims(2 * l.r_max + margin, l.count, l.cells, l.length);
      e.binning += static_cast<double>(l.cells[0]) * l.cells[1] * l.cells[2];
    }
    for (std::size_t i = 0; i < n; i += stride) {
      const int own = level_for(2 * p.radius[i], l1, m);
      for (int k = 1; k <= own; ++k) {
        const Lv& l = lv[static_cast<std::size_t>(k)];
        if (l.count == 0) continue;
        const double r = p.radius[i] + l.r_max + margin;
        double cells = 1, fraction = 1;
        for (int a = 0; a < 3; ++a) {
          const double c = std::min<double>(l.cells[a], 1 + 2 * r / l.length[a]);
          cells *= c;
          fraction *= c / l.cells[a];
        }
        e.cells += weight * cells;
        e.candidates += weight * fraction * static_cast<double>(l.count);
      }
    }
    result.push_back(e);
  }
  return result;
}

int MultiLevelGrid::choose_levels(const Particles& p, const Domain& domain, double margin, double d_min,
                                  double d_max) {
  double volume = 1;
  for (int k = 0; k < 3; ++k) volume *= std::max(extent_[k], d_max);
  // The choice is kept while the estimate's inputs stay close (the block-step integrator
  // rebuilds its lists often, with radii grown by each grain's reach); the pairs found do
  // not depend on the number of levels, only the search's speed does.
  auto near = [](double a, double b, double ratio) { return a <= ratio * b && b <= ratio * a; };
  const bool same = auto_levels_ > 0 && near(static_cast<double>(auto_n_), static_cast<double>(p.size()), 1.1) &&
                    near(auto_key_[0], d_min, 1.25) && near(auto_key_[1], d_max, 1.25) &&
                    near(auto_key_[2], margin, 1.25) && near(volume, auto_key_[3], 1.5);
  if (same) return auto_levels_;
  const auto estimates = estimate(p, domain, margin);
  auto best = std::min_element(estimates.begin(), estimates.end(),
                               [](const Estimate& a, const Estimate& b) { return a.total() < b.total(); });
  auto_levels_ = best->levels;
  auto_n_ = p.size();
  auto_key_[0] = d_min, auto_key_[1] = d_max, auto_key_[2] = margin, auto_key_[3] = volume;
  return auto_levels_;
}

void MultiLevelGrid::find_pairs(const Particles& p, const Domain& domain, double margin, std::vector<Pair>& out) {
  out.clear();
  const std::size_t n = p.size();
  if (n == 0) return;
  const auto [r_lo, r_hi] = std::minmax_element(p.radius.begin(), p.radius.end());
  const double d_min = 2 * *r_lo, d_max = 2 * *r_hi;
  span(p, domain);
  l1_ = top_level_size(domain.length(0), d_max);
  const int m = forced_levels_ > 0 ? std::min(forced_levels_, kMaxLevels) : choose_levels(p, domain, margin, d_min, d_max);

  // Levels: members, largest radius, cells.
  levels_.assign(static_cast<std::size_t>(m), Level{});
  level_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int k = level_for(2 * p.radius[i], l1_, m);
    level_of_[i] = static_cast<std::uint8_t>(k);
    Level& l = levels_[static_cast<std::size_t>(k - 1)];
    ++l.count;
    l.r_max = std::max(l.r_max, p.radius[i]);
  }
  for (Level& l : levels_) {
    if (l.count == 0) continue;
    cell_dims(2 * l.r_max + margin, l.count, l.cells, l.length);
    l.start.assign(static_cast<std::size_t>(l.cells[0]) * l.cells[1] * l.cells[2] + 1, 0);
  }
  // Counting sort of every particle into its level's cells (ascending index within a cell).
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Level& l = levels_[static_cast<std::size_t>(level_of_[i] - 1)];
    int c[3];
    for (int k = 0; k < 3; ++k) {
      const int ck = static_cast<int>(std::floor((p.position[i][k] - origin_[k]) / l.length[k]));
      c[k] = domain.periodic[k] ? ((ck % l.cells[k]) + l.cells[k]) % l.cells[k] : std::clamp(ck, 0, l.cells[k] - 1);
    }
    cell_of_[i] = (c[2] * l.cells[1] + c[1]) * l.cells[0] + c[0];
    ++l.start[static_cast<std::size_t>(cell_of_[i]) + 1];
  }
  for (Level& l : levels_) {
    if (l.count == 0) continue;
    for (std::size_t c = 1; c < l.start.size(); ++c) l.start[c] += l.start[c - 1];
    l.items.resize(l.count);
  }
  {
    std::vector<std::vector<int>> fill(levels_.size());
    for (std::size_t k = 0; k < levels_.size(); ++k)
      if (levels_[k].count) fill[k].assign(levels_[k].start.begin(), levels_[k].start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k = level_of_[i] - 1u;
      levels_[k].items[static_cast<std::size_t>(fill[k][static_cast<std::size_t>(cell_of_[i])]++)] = {
          p.position[i], p.radius[i], static_cast<std::uint32_t>(i)};
    }
  }

  // Search: each particle its own level (j > i) and every coarser level.
  std::vector<std::vector<Pair>> per_thread;  // freed on return: the lists are the big memory
  for_each_range(n, per_thread, [&](std::size_t begin, std::size_t end, std::vector<Pair>& local) {
    std::vector<int> axis[3];
    for (auto& a : axis) a.resize(8);
    for (std::size_t i = begin; i < end; ++i) {
      const Vec3& xi = p.position[i];
      const double ri = p.radius[i];
      const int own = level_of_[i];
      for (int k = 1; k <= own; ++k) {
        const Level& l = levels_[static_cast<std::size_t>(k - 1)];
        if (l.count == 0) continue;
        const double r = ri + l.r_max + margin;
        int m_axis[3];
        for (int a = 0; a < 3; ++a) {
          int lo, hi;
          cover(xi[a], r, origin_[a], l.length[a], lo, hi);
          const std::size_t need = static_cast<std::size_t>(std::min(hi - lo + 1, l.cells[a]));
          if (axis[a].size() < need) axis[a].resize(need);
          m_axis[a] = axis_cells(lo, hi, l.cells[a], domain.periodic[a], axis[a].data());
        }
        const bool same_level = k == own;
        for (int cz = 0; cz < m_axis[2]; ++cz)
          for (int cy = 0; cy < m_axis[1]; ++cy) {
            const int row = (axis[2][static_cast<std::size_t>(cz)] * l.cells[1] + axis[1][static_cast<std::size_t>(cy)]) * l.cells[0];
            for (int cx = 0; cx < m_axis[0]; ++cx) {
              const std::size_t cell = static_cast<std::size_t>(row + axis[0][static_cast<std::size_t>(cx)]);
              const int s_end = l.start[cell + 1];
              for (int s = l.start[cell]; s < s_end; ++s) {
                const Item& it = l.items[static_cast<std::size_t>(s)];
                if (same_level && it.id <= i) continue;
                const double reach = ri + it.r + margin;
                if (norm2(domain.separation(xi, it.x)) < reach * reach) {
                  const auto ii = static_cast<std::uint32_t>(i);
                  local.push_back(ii < it.id ? Pair{ii, it.id} : Pair{it.id, ii});
                }
              }
            }
          }
      }
    }
  });

  // Order by (i, j): counting sort on i, then each particle's partners sorted.
  first_.assign(n + 1, 0);
  std::size_t total = 0;
  for (const auto& local : per_thread) {
    total += local.size();
    for (const Pair& q : local) ++first_[q.i + 1];
  }
  for (std::size_t i = 0; i < n; ++i) first_[i + 1] += first_[i];
  out.resize(total);
  {
    std::vector<std::uint32_t> fill(first_.begin(), first_.end() - 1);
    for (const auto& local : per_thread)
      for (const Pair& q : local) out[fill[q.i]++] = q;
  }
  parallel_for(n, [&](std::size_t i) {
    if (first_[i + 1] - first_[i] > 1)
      std::sort(out.begin() + first_[i], out.begin() + first_[i + 1], [](const Pair& a, const Pair& b) { return a.j < b.j; });
  });
}

}  // namespace tsubu
