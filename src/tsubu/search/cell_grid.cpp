#include <algorithm>
#include <cmath>

#include "tsubu/core/parallel.hpp"
#include "tsubu/search/pair_search.hpp"

namespace tsubu {

void grid_span(const Particles& p, const Domain& domain, double origin[3], double extent[3]) {
  for (int k = 0; k < 3; ++k) {
    if (domain.periodic[k]) {
      origin[k] = domain.lower[k];
      extent[k] = domain.length(k);
    } else {
      double lo = p.position[0][k], hi = lo;
      for (std::size_t i = 1; i < p.size(); ++i) lo = std::min(lo, p.position[i][k]), hi = std::max(hi, p.position[i][k]);
      origin[k] = lo;
      extent[k] = hi - lo;
    }
  }
}

void grid_cells(const double extent[3], double size, std::size_t items, int cells[3], double length[3]) {
  const double max_cells = 4.0 * static_cast<double>(items) + 27.0;
  // Cells smaller than the longest extent over max_cells are too many along that axis
  // anyway; starting there bounds the loop for any size (0, subnormal or NaN included).
  const double smallest = std::max({extent[0], extent[1], extent[2]}) / max_cells;
  if (!(size >= smallest)) size = smallest;
  for (;; size *= 1.25) {
    double total = 1;
    for (int k = 0; k < 3; ++k) total *= std::max(1.0, std::floor(extent[k] / size));
    if (total <= max_cells) break;
  }
  for (int k = 0; k < 3; ++k) {
    cells[k] = std::max(1, static_cast<int>(std::floor(extent[k] / size)));
    length[k] = extent[k] > 0 ? extent[k] / cells[k] : size;
  }
}

int CellGrid::neighbours(const Domain& domain, int k, int c, int* out_cells) const {
  int count = 0;
  for (int o = -1; o <= 1; ++o) {
    int nc = c + o;
    if (domain.periodic[k]) nc = (nc + cells_[k]) % cells_[k];
    else if (nc < 0 || nc >= cells_[k]) continue;
    if (std::find(out_cells, out_cells + count, nc) == out_cells + count) out_cells[count++] = nc;
  }
  return count;
}

void CellGrid::bin(const Particles& p, const Domain& domain, double cell_size) {
  const std::size_t n = p.size();
  double extent[3];
  grid_span(p, domain, origin_, extent);
  grid_cells(extent, cell_size, n, cells_, cell_length_);
  const std::size_t n_cells = static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2];
  cell_of_.resize(n);
  cell_start_.assign(n_cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    int c[3];
    for (int k = 0; k < 3; ++k) {
      const int ck = static_cast<int>(std::floor((p.position[i][k] - origin_[k]) / cell_length_[k]));
      c[k] = std::clamp(ck, 0, cells_[k] - 1);  // non-periodic overshoot and round-off
    }
    cell_of_[i] = (c[2] * cells_[1] + c[1]) * cells_[0] + c[0];
    ++cell_start_[static_cast<std::size_t>(cell_of_[i]) + 1];
  }
  for (std::size_t c = 0; c < n_cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_items_.resize(n);
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) cell_items_[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of_[i])]++)] = static_cast<std::uint32_t>(i);
}

void CellGrid::find_pairs(const Particles& p, const Domain& domain, double margin, std::vector<Pair>& out) {
  out.clear();
  const std::size_t n = p.size();
  if (n == 0) return;
  const double d_max = 2.0 * *std::max_element(p.radius.begin(), p.radius.end());
  bin(p, domain, d_max + margin);

  std::vector<std::vector<Pair>> per_thread;  // freed on return: the lists are the big memory
  for_each_range(n, per_thread, [&](std::size_t begin, std::size_t end, std::vector<Pair>& local) {
    std::vector<std::uint32_t> found;
    for (std::size_t i = begin; i < end; ++i) {
      found.clear();
      for_each_near(i, domain, [&](std::uint32_t j) {
        if (j <= i) return;
        const double reach = p.radius[i] + p.radius[j] + margin;
        if (norm2(domain.separation(p.position[i], p.position[j])) < reach * reach) found.push_back(j);
      });
      std::sort(found.begin(), found.end());
      for (std::uint32_t j : found) local.push_back({static_cast<std::uint32_t>(i), j});
    }
  });
  std::size_t total = 0;
  for (const auto& local : per_thread) total += local.size();
  out.reserve(total);
  for (const auto& local : per_thread) out.insert(out.end(), local.begin(), local.end());
}

}  // namespace tsubu
