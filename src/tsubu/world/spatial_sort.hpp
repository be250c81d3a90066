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

}  // namespace tsubu
