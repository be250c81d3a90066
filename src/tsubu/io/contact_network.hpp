// The contact network of a state: every touching contact with its geometry and forces, as
// LIGGGHTS' compute pair/gran/local lists them, and its CSV form (docs/cli.md, output folder).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

struct NetworkContact {
  std::int64_t id_i = 0;  // particle ids
  std::int64_t id_j = -1; // -1 for a wall contact
  int wall = -1;          // wall index, -1 for a pair
  std::uint32_t element = 0;  // the wall element (World::wall_elements): a mesh's triangle
  Vec3 centre_i;          // m, particle i's centre
  Vec3 point;             // m, mid-overlap on the line of centres (pair) or on the plane (wall)
  Vec3 branch;            // m, from i's centre to j's (nearest periodic image) or to `point` (wall)
  Vec3 normal_force, tangential_force;  // N, on particle i
  double overlap = 0;     // m
  ContactHistory history;
};

// The network from the force field's contacts (ForceField::touching_contacts): each pair seen
// from its particle with the smaller id, pairs by their ids, then walls by particle id and
// wall: the same whatever the particles' numbering.
std::vector<NetworkContact> contact_network(const World& world, const std::vector<ContactRecord>& contacts);

// One row per contact, a header naming each column with its unit; rolling: with the rolling
// spring's columns (a scenario whose laws resist rolling). Checked writes.
void write_contacts_csv(const std::string& path, const std::vector<NetworkContact>& contacts, double time, bool rolling);

}  // namespace tsubu
