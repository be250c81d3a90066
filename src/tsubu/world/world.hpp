// Everything a run evolves: box, walls, particles, contacts with their histories, clock.
// The physics that acts on it (materials, laws, gravity, fluid, search) is the Model
// (model/model.hpp), beside it.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "tsubu/world/contact_list.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

struct World {
  Domain domain;
  std::vector<Wall> walls;
  Particles particles;
  double dt = 0;           // s
  double time = 0;         // s
  std::int64_t step = 0;
  ContactList contacts;  // neighbour lists with their histories (world/contact_list.hpp)
  // A run split among processes (ranks/decomposition.hpp): the last `ghosts` particles are
  // copies of other processes' particles, which those integrate; 0 in one process.
  std::size_t ghosts = 0;
  std::size_t owned() const { return particles.size() - ghosts; }
  // The particle ids each [[particles]] source gave, [first, last) in the order of the
  // scenario (an inflow: from its first grain on); set by build_world.
  std::vector<std::pair<std::int64_t, std::int64_t>> source_ids;
};

}  // namespace tsubu
