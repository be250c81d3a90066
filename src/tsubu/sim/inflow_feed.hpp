// The scenario's inflow (source = "inflow") fed into a Simulation: at every step boundary
// the grains due by then enter the box (source/inflow.hpp, admit_due) and join the run
// (Simulation::particles_added). Its grains get the ids first_id, first_id + 1, ... in the
// order the column releases them (first_id = the particles the other sources made).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu/source/inflow.hpp"

namespace tsubu {

class InflowFeed {
 public:
  InflowFeed(const Scenario& sc, const ParticleSource& src, std::int64_t first_id);

  // The grains due at sim's time enter (those that find their place taken wait); call
  // between steps only (at multiples of dt).
  void admit(Simulation& sim);

  std::int64_t first_id() const { return first_id_; }
  // The mass of the inflow's grains in the box (kg).
  double mass_entered(const World& w) const;
  // inflow_rates and inflow_counts (source/inflow.hpp), and inflow_F_measured: the mass
  // entered over the time so far (kg/s; 0 at t = 0).
  std::vector<std::pair<std::string, double>> results(const World& w) const;

  // The stream's state for checkpoints (encode_inflow_state), and back.
  std::string state() const { return encode_inflow_state(stream_.state()); }
  void restore(std::string_view bytes) { stream_.restore(decode_inflow_state(bytes)); }

 private:
  InflowStream stream_;
  int material_;
  std::int64_t first_id_;
};

// The names of InflowFeed::results, in its order (they do not depend on the state).
std::vector<std::string> inflow_result_names();

// The unit of one of InflowFeed::results ("kg/s", "m", ...; "" for numbers and counts).
std::string inflow_result_unit(const std::string& name);

}  // namespace tsubu
