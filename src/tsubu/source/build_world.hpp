// Scenario -> World: particles from every source, contact laws, and the checks that need
// the particles (inside the domain, no overlapping input, periodic box large enough).
#pragma once
#include "tsubu/scenario/result_names.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/inflow.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// Inflow sources create no particle here: their grains arrive during the run.
World build_world(const Scenario& scenario);

// The column of the scenario's inflow source (inflow_source, scenario/result_names.hpp). The
// stream is InflowStream(inflow_column(sc, *src), sc.seed); its grains get the ids after
// build_world's (first_id = the number of particles build_world made).
InflowColumn inflow_column(const Scenario& scenario, const ParticleSource& src);

// The box, materials, walls, gravity, clock settings and contact laws, without particles
// (tsubu resume takes those from a checkpoint).
World build_empty_world(const Scenario& scenario);

}  // namespace tsubu
