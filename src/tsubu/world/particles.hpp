// The particle store: one array per quantity (structure of arrays), indexed 0..size()-1.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tsubu/core/vec3.hpp"

namespace tsubu {

struct Particles {
  std::vector<std::int64_t> id;       // user-visible id, stable for the whole run
  std::vector<int> material;          // index into Model::materials
  std::vector<double> radius;         // m
  std::vector<double> mass;           // kg
  std::vector<double> translational_mass;  // kg, mass + the fluid's added mass C_M rho_f V: the
                                           // inertia the integrators divide forces by (set by
                                           // ForceField::admit_new_particles from Model::fluid)
  std::vector<double> inertia;        // kg m^2, solid sphere: 2/5 m R^2
  std::vector<Vec3> position;         // m
  std::vector<Vec3> velocity;         // m/s
  std::vector<Vec3> omega;            // rad/s
  std::vector<Vec3> force;            // N, total of the last evaluation
  std::vector<Vec3> torque;           // N m
  std::vector<int> contact_count;     // contacts (pairs and walls) at the last evaluation

  std::size_t size() const { return radius.size(); }

  // The kinetic energies of particle i, J.
  double translational_energy(std::size_t i) const { return 0.5 * mass[i] * norm2(velocity[i]); }
  double rotational_energy(std::size_t i) const { return 0.5 * inertia[i] * norm2(omega[i]); }

  // f(array) for every per-particle array, always in this order (the checkpoint format's),
  // to move, copy or store particles with all they carry.
  template <class F>
  void for_each_array(F&& f) { each_array(*this, f); }
  template <class F>
  void for_each_array(F&& f) const { each_array(*this, f); }

  // The indices in the order of the ids: the order every output lists particles in, so that
  // a file does not depend on how the particles are numbered (a spatial sort, processes).
  std::vector<std::size_t> in_id_order() const;

  void add(std::int64_t pid, int mat, double diameter, double density, const Vec3& x, const Vec3& v) {
    const double r = 0.5 * diameter;
    const double m = density * (4.0 / 3.0) * M_PI * r * r * r;
    id.push_back(pid);
    material.push_back(mat);
    radius.push_back(r);
    mass.push_back(m);
    translational_mass.push_back(m);
    inertia.push_back(0.4 * m * r * r);
    position.push_back(x);
    velocity.push_back(v);
    omega.push_back({});
    force.push_back({});
    torque.push_back({});
    contact_count.push_back(0);
  }

 private:
  template <class Self, class F>
  static void each_array(Self& p, F& f) {
    f(p.id), f(p.material), f(p.radius), f(p.mass), f(p.translational_mass), f(p.inertia);
    f(p.position), f(p.velocity), f(p.omega), f(p.force), f(p.torque), f(p.contact_count);
  }
};

inline std::vector<std::size_t> Particles::in_id_order() const {
  std::vector<std::size_t> order(size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
  return order;
}

}  // namespace tsubu
