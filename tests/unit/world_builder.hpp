// Small worlds for tests: one material, one contact law, particles and walls added by hand.
#pragma once
#include "tsubu/forces/force_field.hpp"
#include "tsubu/integrate/integrators.hpp"
#include "tsubu/model/model.hpp"

namespace tsubu::testing {

// A world and the model it runs under, built by hand (auto [w, model] = make_world(...)).
struct Bed {
  World world;
  Model model;
};

// The force evaluation the fixed-step integrators call, for a world stepped without a
// Simulation (so without the sort schedule): velocity_verlet_step(w, evaluation(f, w)).
inline auto evaluation(ForceField& f, World& w) {
  return [&f, &w](double fluid_lead) { f.compute(w, fluid_lead); };
}

inline Bed make_world(const Material& m, const ContactSpec& spec, double dt, const Vec3& gravity = {}) {
  Bed b;
  b.world.domain = {{-10, -10, -10}, {10, 10, 10}, {false, false, false}};
  b.world.dt = dt;
  b.model.materials = {m};
  b.model.laws.n_materials = 1;
  b.model.laws.laws = {make_pair_law(spec, m, m)};
  b.model.gravity = gravity;
  return b;
}

// A wall of its own material (index 1) so that a "rigid" plane can be modelled.
inline void add_wall_material(Model& model, const Material& wall, const ContactSpec& spec) {
  model.materials.push_back(wall);
  model.laws.n_materials = 2;
  model.laws.laws.clear();
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) model.laws.laws.push_back(make_pair_law(spec, model.materials[a], model.materials[b]));
}

inline ContactSpec spec_of(const char* normal, const char* tangential, double e, double mu = 0) {
  ContactSpec s;
  s.normal = normal;
  s.tangential = tangential;
  s.restitution = e;
  s.friction = mu;
  return s;
}

}  // namespace tsubu::testing
