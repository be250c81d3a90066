// The scenario's grains that arrive during the run, fed into a Simulation (Simulation::feed):
// the inflow's column (source = "inflow", source/inflow.hpp) or an insertion region (source =
// "insertion", source/insertion.hpp). At every step boundary the grains due by then enter
// the box (source/admission.hpp) and the Simulation makes them join the run. Its grains get
// the ids first_id, first_id + 1, ... in the order the source releases them (first_id = the
// particles the other sources made).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/admission.hpp"
#include "tsubu/source/inflow.hpp"
#include "tsubu/source/insertion.hpp"
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
  // The sizes of the grains it releases.
  const SizeDistribution& sizes() const;
  // The stream has released its last grain (its mass limit reached, none waiting).
  bool ended() const;
  // inflow_rates (the column) or insertion_rates: what `tsubu check` prints.
  std::vector<std::pair<std::string, double>> rates() const;
  // The mass of the inflow's grains in the box (kg).
  double mass_in_box(const World& w) const;
  // inflow_rates and inflow_counts (source/inflow.hpp), and inflow_F_measured: the mass
  // entered (Simulation::inflow_mass_entered) over the time so far (kg/s; 0 at t = 0).
  std::vector<std::pair<std::string, double>> results(double time, double mass_entered) const;

  // The stream's state for checkpoints (encode_inflow_state), and back.
  std::string state() const;
  void restore(std::string_view bytes);

 private:
  std::variant<InflowStream, InsertionStream> stream_;
  int material_;
  std::int64_t first_id_;
};

// The unit of one of InflowFeed::results ("kg/s", "m", ...; "" for numbers and counts).
std::string inflow_result_unit(const std::string& name);

}  // namespace tsubu
