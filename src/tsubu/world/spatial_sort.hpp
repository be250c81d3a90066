// Spatial sorting: the particles are renumbered along a Z-order (Morton) curve, so that
// grains close in space are close in memory and the force loop's reads of partners hit the
// cache. Ids and every per-particle array move with their particle; the contacts follow
// (their histories are stored by particle id, so none changes).
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/world/world.hpp"

namespace tsubu {

// Reorders world.particles by the Morton code of cells of the smallest diameter (ties keep
// their order) and renumbers the contact lists to match (ContactList::renumber), sorted by
// (i, j) again. Returns order[new] = old.
std::vector<std::uint32_t> sort_spatially(World& world);

// Removes the particles flagged in `gone` (one flag per particle), the others keeping their
// order (a split run's copies of other processes' particles stay last: World::ghosts counts
// those kept), with their contacts (ContactList::renumber). Returns order[new] = old.
std::vector<std::uint32_t> remove_particles(World& world, const std::vector<char>& gone);

// Another per-particle store follows the same renumbering: a[new] = a[order[new]] (order as
// sort_spatially returns it). In place: the array keeps its storage, so views into it (the
// Python binding's NumPy arrays) stay valid across a sort. Any order of the same form will
// do (Particles::in_id_order()'s, for one).
template <class T, class Index>
void permute(std::vector<T>& a, const std::vector<Index>& order) {
  const std::vector<T> unsorted = a;
  for (std::size_t k = 0; k < order.size(); ++k) a[k] = unsorted[order[k]];
}

}  // namespace tsubu
