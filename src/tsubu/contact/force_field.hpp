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

// Neighbour lists (pairs and walls within `skin` of touching) are rebuilt, carrying every
// history over, once some particle has moved more than skin/2 since the last build; in
// between, each step only evaluates the listed pairs.
class ForceField {
 public:
  // Evaluates every touching contact and sums forces and torques (with gravity) into
  // world.particles. Throws NumericalError when an overlap exceeds world.overlap_limit or
  // a force is not finite.
  void compute(World& world);

  const ContactTotals& totals() const { return totals_; }
  std::uint64_t evaluations() const { return evaluations_; }  // contact force evaluations
  std::uint64_t rebuilds() const { return rebuilds_; }        // neighbour-list builds

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
  std::vector<Vec3> built_at_;  // positions at the last build
  double skin_ = 0;
  ContactTotals totals_;
  std::uint64_t evaluations_ = 0, rebuilds_ = 0;

  bool needs_rebuild(const World& world) const;
  void rebuild(World& world);
  void find_wall_contacts(const World& world, std::vector<Pair>& out);
  void evaluate_pairs(World& world);
  void evaluate_walls(World& world);
  void accumulate(World& world);
};

}  // namespace tsubu
