// The physics of a run, beside its state (world/world.hpp): materials, contact laws,
// gravity, the still fluid, and how contacts are searched and checked. Built once from the
// scenario (source/build_world.hpp) and never changed by a step; every process of a run
// holds the same copy.
#pragma once
#include <vector>

#include "tsubu/contact/law.hpp"
#include "tsubu/fluid/fluid.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

struct Model {
  std::vector<Material> materials;  // indexed by Particles::material and Wall::material
  LawTable laws;                    // the contact law of every material pair
  Vec3 gravity;                     // m/s^2
  Fluid fluid;                      // still fluid around the particles; disabled by default
  SearchSpec search;                // contact search method of the neighbour-list builds
  double overlap_limit = 0.1;       // largest overlap / smaller diameter before the run stops
  double skin = 0;                  // m, neighbour-list margin; 0: a tenth of the smallest diameter
};

}  // namespace tsubu
