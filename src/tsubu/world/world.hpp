// Everything a run evolves: particles, walls, box, materials, contact laws, contacts, clock.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/contact/law.hpp"
#include "tsubu/fluid/fluid.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

// An entry of the neighbour list: a pair closer than the skin, with its contact history
// kept beside it. For particle pairs `j` is the partner (i < j); for walls it is the wall
// index. Lists are sorted by (i, j). `touching` says whether the pair overlaps now; the
// history of a pair that does not is empty.
struct Contact {
  std::uint32_t i, j;
  bool touching = false;
  ContactHistory history;
};

struct World {
  Domain domain;
  std::vector<Material> materials;
  std::vector<Wall> walls;
  Particles particles;
  LawTable laws;
  Vec3 gravity;            // m/s^2
  Fluid fluid;             // still fluid around the particles; disabled by default
  double dt = 0;           // s
  double time = 0;         // s
  std::int64_t step = 0;
  double overlap_limit = 0.1;  // largest overlap / smaller diameter before the run stops
  double skin = 0;             // m, neighbour-list margin; 0: a tenth of the smallest diameter
  std::vector<Contact> pair_contacts;
  std::vector<Contact> wall_contacts;
  SearchSpec search;  // contact search method of the neighbour-list builds
  // The particle ids each [[particles]] source gave, [first, last) in the order of the
  // scenario (an inflow: from its first grain on); set by build_world.
  std::vector<std::pair<std::int64_t, std::int64_t>> source_ids;
};

}  // namespace tsubu
