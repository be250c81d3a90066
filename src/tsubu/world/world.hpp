// Everything a run evolves: particles, walls, box, materials, contact laws, contacts, clock.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/contact/contact_list.hpp"
#include "tsubu/contact/law.hpp"
#include "tsubu/fluid/fluid.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

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
  ContactList contacts;  // neighbour lists with their histories (contact/contact_list.hpp)
  SearchSpec search;  // contact search method of the neighbour-list builds
  // The particle ids each [[particles]] source gave, [first, last) in the order of the
  // scenario (an inflow: from its first grain on); set by build_world.
  std::vector<std::pair<std::int64_t, std::int64_t>> source_ids;
};

}  // namespace tsubu
