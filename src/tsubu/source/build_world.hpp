// Scenario -> World: particles from every source, contact laws, and the checks that need
// the particles (inside the domain, no overlapping input, periodic box large enough).
#pragma once
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

World build_world(const Scenario& scenario);

// The box, materials, walls, gravity, clock settings and contact laws, without particles
// (tsubu resume takes those from a checkpoint).
World build_empty_world(const Scenario& scenario);

}  // namespace tsubu
