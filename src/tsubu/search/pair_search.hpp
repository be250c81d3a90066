// Contact search. Every search (linked-cell grid, multi-level grid) fills the same
// output: all pairs i < j with |x_i - x_j| < R_i + R_j + margin, sorted by (i, j), the same
// for every thread count.
#pragma once
#include <cstdint>
#include <variant>
#include <vector>

#include "tsubu/world/contact_list.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

// Where a grid lies along each axis: the box along periodic axes, the particles' extent
// along the others (a few grains in a large box cost nothing).
void grid_span(const Particles& p, const Domain& domain, double origin[3], double extent[3]);

// Cells per axis no smaller than `size`, enlarged until there are at most about four per
// item, and their lengths.
void grid_cells(const double extent[3], double size, std::size_t items, int cells[3], double length[3]);

// Linked-cell grid: cells no smaller than the largest diameter (+ margin), particles
// binned by a counting sort each call, 27-cell stencil with periodic wrap. Along periodic
// axes the grid spans the box; along the others, only the particles' extent. Cells are
// enlarged when needed so that there are at most about 4 per particle.
class CellGrid {
 public:
  void find_pairs(const Particles& p, const Domain& domain, double margin, std::vector<Pair>& out);

  // For callers that walk the cells themselves (the input overlap check stops at the first
  // offence instead of listing every pair): bins the particles into cells no smaller than
  // `cell_size`, then f(j) for every particle j in the cells around particle i's (27-cell
  // stencil, each cell once, wrapped along periodic axes; i itself included).
  void bin(const Particles& p, const Domain& domain, double cell_size);
  template <class F>
  void for_each_near(std::size_t i, const Domain& domain, F&& f) const {
    const int c = cell_of_[i];
    const int cx = c % cells_[0], cy = (c / cells_[0]) % cells_[1], cz = c / (cells_[0] * cells_[1]);
    int nx[3], ny[3], nz[3];
    const int mx = neighbours(domain, 0, cx, nx), my = neighbours(domain, 1, cy, ny), mz = neighbours(domain, 2, cz, nz);
    for (int a = 0; a < mz; ++a)
      for (int b = 0; b < my; ++b)
        for (int d = 0; d < mx; ++d) {
          const std::size_t cell = static_cast<std::size_t>((nz[a] * cells_[1] + ny[b]) * cells_[0] + nx[d]);
          for (int s = cell_start_[cell]; s < cell_start_[cell + 1]; ++s) f(cell_items_[static_cast<std::size_t>(s)]);
        }
  }

 private:
  int cells_[3] = {1, 1, 1};
  double cell_length_[3] = {1, 1, 1};
  double origin_[3] = {0, 0, 0};
  std::vector<int> cell_of_;       // per particle
  std::vector<int> cell_start_;    // per cell + 1, offsets into cell_items_
  std::vector<std::uint32_t> cell_items_;

  // Distinct neighbour cell indices along axis k: {c-1, c, c+1} wrapped (periodic) or clipped.
  int neighbours(const Domain& domain, int k, int c, int* out_cells) const;
};


// Multi-level grid ("multi-size mesh", docs/engine.md, "Contact search"): with base
// length L = the domain's x length, level K = 1..M has nominal size l_K = 2^-(K-1+K0) L,
// l_1 the smallest power-of-two fraction of L not below the largest diameter. A particle of
// diameter d lives on level K with l_{K+1} < d <= l_K (the finest level whose cells are not
// smaller than it; level M takes every smaller one). Each level is its own linked-cell grid,
// binned by a counting sort each call, with cells no smaller than the largest diameter on
// that level (+ margin), so a level's cells are never larger than l_K + margin; the span,
// periodic wrap and the cap of about 4 cells per particle (of that level) are CellGrid's.
// A particle searches its own level (27 cells, partners j > i) and every coarser level
// within R_p + r_max(level) + margin; pairs with a finer partner are found from the
// partner's side, so each pair is found once. Same output contract as CellGrid.
// The number of levels is chosen by minimising estimate() unless set by set_levels().
class MultiLevelGrid {
 public:
  static constexpr int kMaxLevels = 24;

  explicit MultiLevelGrid(int levels = 0) : forced_levels_(levels) {}
  void set_levels(int levels) { forced_levels_ = levels; }  // 0: automatic
  void find_pairs(const Particles& p, const Domain& domain, double margin, std::vector<Pair>& out);

  // Of the last find_pairs: the number of levels, each particle's level (1 = coarsest), l_1.
  int levels() const { return static_cast<int>(levels_.size()); }
  const std::vector<std::uint8_t>& level_of() const { return level_of_; }
  double top_level_size() const { return l1_; }

  // l_1 = 2^-K0 L with 2^-(K0+1) L < d_max <= 2^-K0 L.
  static double top_level_size(double base_length, double d_max);
  // The level of diameter d: K with l_{K+1} < d <= l_K, clamped to 1..levels.
  static int level_for(double d, double l1, int levels);

  // Estimated cost of one find_pairs with M levels: cells visited and candidate pairs
  // tested (and cells cleared by the binning), from the particles' diameters and the volume
  // they fill. Entry M-1 is for M levels, M = 1..the finest level that holds a particle.
  // total() weighs a cell visit as kCellCost candidate tests: fitted to the forced-level
  // timings of bench/bench_search.cpp (bench/results/search_scaling.md: ~8.8 ns per cell,
  // ~1.9 ns per candidate on the reference machine).
  static constexpr double kCellCost = 4;
  struct Estimate {
    int levels = 0;
    double cells = 0, candidates = 0, binning = 0;
    double total() const { return kCellCost * cells + candidates + binning; }
  };
  std::vector<Estimate> estimate(const Particles& p, const Domain& domain, double margin) const;

 private:
  struct Item {
    Vec3 x;
    double r;
    std::uint32_t id;
  };
  struct Level {
    int cells[3] = {1, 1, 1};
    double length[3] = {1, 1, 1};
    double r_max = 0;
    std::size_t count = 0;
    std::vector<int> start;  // per cell + 1, offsets into items
    std::vector<Item> items;
  };
  int forced_levels_ = 0;
  double l1_ = 0;
  double origin_[3] = {0, 0, 0}, extent_[3] = {0, 0, 0};
  std::vector<Level> levels_;
  std::vector<std::uint8_t> level_of_;
  std::vector<int> cell_of_;
  std::vector<std::uint32_t> first_;
  // Automatic level count of the last choice and what it was chosen for.
  int auto_levels_ = 0;
  std::size_t auto_n_ = 0;
  double auto_key_[4] = {0, 0, 0, 0};  // d_min, d_max, margin, volume

  void span(const Particles& p, const Domain& domain);
  void cell_dims(double size, std::size_t count, int* cells, double* length) const;
  int choose_levels(const Particles& p, const Domain& domain, double margin, double d_min, double d_max);
};

// Which search ForceField uses ([search] in a scenario).
struct SearchSpec {
  enum class Method { cell, multilevel };
  Method method = Method::cell;
  int levels = 0;  // multilevel: number of levels, 0 = automatic
  std::int64_t sort_every = 0;  // steps between spatial sorts of the particles (0: never)
};

// Holds the configured search; find_pairs as CellGrid's.
class PairSearch {
 public:
  void configure(const SearchSpec& spec) {
    if (spec.method == SearchSpec::Method::cell) {
      if (!std::holds_alternative<CellGrid>(impl_)) impl_ = CellGrid{};
    } else {
      if (!std::holds_alternative<MultiLevelGrid>(impl_)) impl_ = MultiLevelGrid{};
      std::get<MultiLevelGrid>(impl_).set_levels(spec.levels);
    }
  }
  void find_pairs(const Particles& p, const Domain& domain, double margin, std::vector<Pair>& out) {
    std::visit([&](auto& s) { s.find_pairs(p, domain, margin, out); }, impl_);
  }

 private:
  std::variant<CellGrid, MultiLevelGrid> impl_;
};

}  // namespace tsubu
