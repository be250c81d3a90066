// Scenario -> World and Model: particles from every source, the contact laws, and the checks
// that need the particles (inside the domain, no overlapping input, periodic box large enough).
#pragma once
#include "tsubu/scenario/result_names.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/model/model.hpp"
#include "tsubu/source/inflow.hpp"
#include "tsubu/source/insertion.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// Inflow sources create no particle here: their grains arrive during the run.
World build_world(const Scenario& scenario);

// The column of the scenario's inflow source (inflow_source, scenario/result_names.hpp). The
// stream is InflowStream(inflow_column(sc, *src), sc.seed); its grains get the ids after
// build_world's (first_id = the number of particles build_world made).
InflowColumn inflow_column(const Scenario& scenario, const ParticleSource& src);
// An insertion source's region, sizes, rates and velocity (source/insertion.hpp).
Insertion insertion_of(const Scenario& scenario, const ParticleSource& src);

// The box, walls and clock settings, without particles (tsubu resume takes those from a
// checkpoint).
World build_empty_world(const Scenario& scenario);

// The materials, contact laws, gravity, fluid, search and limits of the scenario.
Model build_model(const Scenario& scenario);

}  // namespace tsubu
