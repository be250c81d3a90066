// Computes the force and torque on every particle: gravity, the still fluid's forces
// (World::fluid) and all pair and wall contacts.
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

  // Contacts, elastic energy and largest overlap of the last evaluation (a pass over all
  // contacts: call it for output, not every step).
  ContactTotals totals(const World& world) const;
  // Force the particles exert on wall `wall` along minus its normal (positive when pushed),
  // N, from the last evaluation.
  double wall_load(const World& world, std::size_t wall) const;
  std::uint64_t evaluations() const { return evaluations_; }  // contact force evaluations
  std::uint64_t rebuilds() const { return rebuilds_; }        // neighbour-list builds
  // Resuming from a checkpoint: the counters continue; the lists are rebuilt on the next
  // compute from world's contact lists (results do not depend on when lists are built).
  void restore_counters(std::uint64_t evaluations, std::uint64_t rebuilds) { evaluations_ = evaluations, rebuilds_ = rebuilds; }

 private:
  // Per-contact results, one array per quantity (zeros for pairs that do not touch);
  // delta > 0 marks a touching contact. The torques and overlap ratios are not stored: each
  // particle makes them from n x F_t, the overlap and its own radius (64 bytes a contact,
  // not 104).
  // shift_i/j, the position corrections of models P and F, exist only when a law uses them.
  struct Results {
    struct Entry {  // together: the gather reads a partner's contact from one place
      Vec3 force_i, n_x_ft;
      double delta = 0, energy = 0;
    };
    std::vector<Entry> entry;
    std::vector<Vec3> shift_i, shift_j;
    void resize(std::size_t n, bool shifts);
    void set(std::size_t k, const Vec3& f, const Vec3& n_x_f_t, double overlap, double e) { entry[k] = {f, n_x_f_t, overlap, e}; }
    // Torque on a particle of radius r from contact k (the lever arm ends mid-overlap).
    Vec3 torque(std::size_t k, double r) const { return -(r - 0.5 * entry[k].delta) * entry[k].n_x_ft; }
  };
  PairSearch grid_;
  Results pair_results_, wall_results_;
  std::vector<Vec3> built_at_;  // positions at the last build
  bool shifts_ = false;         // some law corrects positions
  std::vector<Vec3> walls_built_at_;  // wall points at the last build
  double skin_ = 0;
  // Contacts of each particle, in ascending contact order. The lists are sorted by (i, j), so
  // the pairs where particle i is the first are the range [first_start_[i], first_start_[i+1]),
  // and those where it is the second, which all come before them, are
  // second_index_[second_start_[i] .. second_start_[i+1]). Its walls: [wall_start_[i], wall_start_[i+1]).
  std::vector<std::uint32_t> first_start_, second_start_, second_index_, wall_start_;
  std::uint64_t evaluations_ = 0, rebuilds_ = 0;

  bool needs_rebuild(const World& world) const;
  void rebuild(World& world);
  void find_wall_contacts(const World& world, std::vector<Pair>& out);
  // Pair contacts go in blocks of kBlock list entries (see evaluate_pair_block).
  static constexpr std::size_t kBlock = 32;
  void evaluate_pairs(World& world);
  // uniform: every material pair has the same model types (LawTable::uniform()).
  void evaluate_pair_block(World& world, std::size_t begin, std::size_t end, bool uniform);
  void evaluate_walls(World& world);
  void index_contacts(const World& world);
  void accumulate(World& world);
  // Overlap over the smaller diameter of contact k (is_wall: a wall contact).
  double overlap_ratio(const World& world, std::size_t k, bool is_wall) const;
  [[noreturn]] void report_overlap(const World& world) const;
};

}  // namespace tsubu
