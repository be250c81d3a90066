// Whole runs of the test scenarios (tests/scenarios/) without output files, for tests that
// compare final states.
#pragma once
#include <omp.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "tsubu/app/simulation_state.hpp"
#include "tsubu/forces/force_field.hpp"
#include "tsubu/integrate/integrators.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu::testing {

inline Scenario test_scenario(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return load_scenario(std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/" + name, overrides);
}

// The scenario's whole run on `threads` threads, its inflow or insertion fed: its final world.
inline World run_scenario(const Scenario& sc, int threads = 1) {
  omp_set_num_threads(threads);
  Simulation sim = new_simulation(sc);  // any integrator
  sim.start();
  sim.advance_to(std::llround(sc.duration / sc.dt));
  omp_set_num_threads(1);
  return std::move(sim.world());
}

inline World run_test_scenario(const std::string& name, const std::vector<std::string>& overrides = {}, int threads = 1) {
  return run_scenario(test_scenario(name, overrides), threads);
}

// A scenario of examples/ (`name` is its path there, e.g. "drum/drum.toml").
inline Scenario example_scenario(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return load_scenario(std::string(TSUBU_SOURCE_DIR) + "/examples/" + name, overrides);
}

inline bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

// The particles' positions, velocities and spins are the same bits in both worlds.
inline bool same_particle_bits(const World& a, const World& b) {
  return same_bits(a.particles.position, b.particles.position) && same_bits(a.particles.velocity, b.particles.velocity) &&
         same_bits(a.particles.omega, b.particles.omega);
}

}  // namespace tsubu::testing
