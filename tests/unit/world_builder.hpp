// Small worlds for tests: one material, one contact law, particles and walls added by hand.
#pragma once
#include "tsubu/contact/force_field.hpp"
#include "tsubu/integrate/integrators.hpp"

namespace tsubu::testing {

inline World make_world(const Material& m, const ContactSpec& spec, double dt, const Vec3& gravity = {}) {
  World w;
  w.domain = {{-10, -10, -10}, {10, 10, 10}, {false, false, false}};
  w.materials = {m};
  w.laws.n_materials = 1;
  w.laws.laws = {make_pair_law(spec, m, m)};
  w.dt = dt;
  w.gravity = gravity;
  return w;
}

// A wall of its own material (index 1) so that a "rigid" plane can be modelled.
inline void add_wall_material(World& w, const Material& wall, const ContactSpec& spec) {
  w.materials.push_back(wall);
  w.laws.n_materials = 2;
  w.laws.laws.clear();
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) w.laws.laws.push_back(make_pair_law(spec, w.materials[a], w.materials[b]));
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
