// Everything a run evolves: particles, walls, box, materials, contact laws, contacts, clock.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/contact/law.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

// A live contact and its history. For particle pairs `j` is the partner (i < j); for walls
// it is the wall index. Lists are kept sorted by (i, j).
struct Contact {
  std::uint32_t i, j;
  ContactHistory history;
};

struct World {
  Domain domain;
  std::vector<Material> materials;
  std::vector<Wall> walls;
  Particles particles;
  LawTable laws;
  Vec3 gravity;            // m/s^2
  double dt = 0;           // s
  double time = 0;         // s
  std::int64_t step = 0;
  double overlap_limit = 0.1;  // largest overlap / smaller diameter before the run stops
  std::vector<Contact> pair_contacts;
  std::vector<Contact> wall_contacts;
};

}  // namespace tsubu
