// The scenario's inflow (source = "inflow"), fed into a Simulation (Simulation::feed): at
// every step boundary the grains due by then enter the box (source/inflow.hpp, admit_due)
// and the Simulation makes them join the run. Its grains get the ids first_id,
// first_id + 1, ... in the order the column releases them (first_id = the particles the
// other sources made).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/inflow.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

class InflowFeed {
 public:
  InflowFeed(const Scenario& sc, const ParticleSource& src, std::int64_t first_id);

  // The grains due at w's time are appended to its particles (those that find their place
  // taken wait); between steps only (at multiples of dt).
  void admit(World& w);
  // The same in a run split among processes: w's own particles are looked at, `agree`
  // makes their verdicts every process's (admit_due), and the grains that enter are appended
  // to `arrivals`, the same on every process.
  void admit(const World& w, Particles& arrivals, const OverlapAgreement& agree);

  std::int64_t first_id() const { return first_id_; }
  const InflowColumn& column() const { return stream_.column(); }
  // The stream has released its last grain (its mass limit reached, none waiting).
  bool ended() const { return stream_.exhausted(); }
  // The mass of the inflow's grains in the box (kg).
  double mass_in_box(const World& w) const;
  // inflow_rates and inflow_counts (source/inflow.hpp), and inflow_F_measured: the mass
  // entered (Simulation::inflow_mass_entered) over the time so far (kg/s; 0 at t = 0).
  std::vector<std::pair<std::string, double>> results(double time, double mass_entered) const;

  // The stream's state for checkpoints (encode_inflow_state), and back.
  std::string state() const { return encode_inflow_state(stream_.state()); }
  void restore(std::string_view bytes) { stream_.restore(decode_inflow_state(bytes)); }

 private:
  InflowStream stream_;
  int material_;
  std::int64_t first_id_;
};

// The unit of one of InflowFeed::results ("kg/s", "m", ...; "" for numbers and counts).
std::string inflow_result_unit(const std::string& name);

}  // namespace tsubu
