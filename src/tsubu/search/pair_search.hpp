// Contact search. Every search (linked-cell grid now, multi-level grid later) fills the same
// output: all pairs i < j with |x_i - x_j| < R_i + R_j + margin, sorted by (i, j), the same
// for every thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

struct Pair {
  std::uint32_t i, j;
};

// Linked-cell grid: cells no smaller than the largest diameter (+ margin), particles
// binned by a counting sort each call, 27-cell stencil with periodic wrap. Along periodic
// axes the grid spans the box; along the others, only the particles' extent. Cells are
// enlarged when needed so that there are at most about 4 per particle.
class CellGrid {
 public:
  void find_pairs(const Particles& p, const Domain& domain, double margin, std::vector<Pair>& out);

 private:
  int cells_[3] = {1, 1, 1};
  double cell_length_[3] = {1, 1, 1};
  double origin_[3] = {0, 0, 0};
  std::vector<int> cell_of_;       // per particle
  std::vector<int> cell_start_;    // per cell + 1, offsets into cell_items_
  std::vector<std::uint32_t> cell_items_;
  std::vector<std::vector<Pair>> per_thread_;

  void bin(const Particles& p, const Domain& domain, double cell_size);
};

}  // namespace tsubu
