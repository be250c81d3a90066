// Computes the force and torque on every particle: gravity plus all pair and wall contacts.
#pragma once
#include <cstdint>
#include <vector>

#include "tsubu/search/pair_search.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// Totals of the last evaluation, for the time series.
struct ContactTotals {
  std::size_t contacts = 0;         // pair + wall contacts
  double elastic_energy = 0;        // J, stored in the normal springs
  double max_overlap_ratio = 0;     // largest overlap / smaller diameter
};

class ForceField {
 public:
  // Finds contacts, carries their history over, evaluates every contact and sums the
  // forces and torques into world.particles. Throws NumericalError when an overlap
  // exceeds world.overlap_limit or a force is not finite.
  void compute(World& world);

  const ContactTotals& totals() const { return totals_; }
  std::uint64_t evaluations() const { return evaluations_; }

 private:
  struct Result {
    Vec3 force_i, torque_i, torque_j;
    double energy, overlap_ratio;
  };
  CellGrid grid_;
  std::vector<Pair> candidates_;
  std::vector<Contact> next_;
  std::vector<Result> pair_results_, wall_results_;
  std::vector<std::vector<Pair>> wall_hits_;
  ContactTotals totals_;
  std::uint64_t evaluations_ = 0;

  void find_wall_contacts(const World& world, std::vector<Pair>& out);
  void evaluate_pairs(World& world);
  void evaluate_walls(World& world);
  void accumulate(World& world);
};

}  // namespace tsubu
