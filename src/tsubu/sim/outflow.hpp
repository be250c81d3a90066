// Open faces of the box (domain.open): a grain whose centre has crossed one has left the
// run. Before each force evaluation of a fixed step, and at the end of each block step (when
// every grain is at its time), the Simulation removes such grains from the world, with their
// contacts, and the Outflow records each one (a Departure, the rows of outflow.csv) and the
// totals (series.csv, run.json, checkpoints).
#pragma once
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "tsubu/world/world.hpp"

namespace tsubu {

// A grain that left through an open face: when (the step reached and its time), which, and
// where and how fast it was when it was found beyond the face.
struct Departure {
  std::int64_t step = 0;
  double time = 0;  // s
  std::int64_t id = 0;
  double diameter = 0, mass = 0;  // m, kg
  Vec3 position, velocity;        // m, m/s
  int face = 0;                   // Domain::departed's number
};

class Outflow {
 public:
  struct Totals {
    std::int64_t count = 0;
    double mass = 0;         // kg, summed in the order of the departures
    double inflow_mass = 0;  // kg, of the inflow's grains among them
  };

  // The grains of the inflow have ids from `first_id` on (their mass is also counted apart).
  void count_inflow_from(std::int64_t first_id) { inflow_first_id_ = first_id; }

  // The grains among w's first `count` particles that are beyond an open face, in the order
  // of their ids, at w's step and time (not yet recorded).
  static std::vector<Departure> departures(const World& w, std::size_t count);
  // Records `gone` in their order (rows of outflow.csv, the totals).
  void record(const std::vector<Departure>& gone);
  // One process: removes from w's particles those beyond an open face, recorded in the order
  // of their ids; the others keep their order, and the contact lists follow
  // (remove_particles). Returns whether any grain left; then `kept` (if given) holds the old
  // index of each particle that stays (kept[new] = old).
  bool remove_departed(World& w, std::vector<std::uint32_t>* kept = nullptr);
  // A split run's mirror (app/observed_run.hpp) takes the totals of its process's outflow,
  // which records every process's departures, and the departures it recorded since.
  void follow(Outflow& source);

  const Totals& totals() const { return totals_; }
  void restore(const Totals& t) { totals_ = t; }
  // The departures since the last call, in the order they were recorded.
  std::vector<Departure> take_departures() { return std::exchange(pending_, {}); }

 private:
  Totals totals_;
  std::int64_t inflow_first_id_ = std::numeric_limits<std::int64_t>::max();
  std::vector<Departure> pending_;
};

}  // namespace tsubu
