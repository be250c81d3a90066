// The time scales of a scenario before it runs (docs/cli.md, "Time scales and the time
// step"): how long its contacts last, the Rayleigh time of its grains, the fluid's drag
// relaxation time, what they ask of the time step, and whether the scenario's dt meets it.
// `tsubu check` prints all of it; `tsubu run` prints the warnings at its start.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// A dt below 1/kStepsPerContact (contact/law.hpp) of the shortest contact is suggested for
// fixed steps; below kFewestContactSteps steps per contact a fixed step is an error in waiting.
constexpr double kFewestContactSteps = 10;
// A fixed dt below this share of the shortest drag relaxation time is suggested (the explicit
// drag's relative error is dt/(2 tau)); above kLargestRelaxationShare of it, a warning.
constexpr double kRelaxationShare = 0.1;
constexpr double kLargestRelaxationShare = 0.5;

// Rayleigh time of a sphere of diameter d: the time a Rayleigh surface wave takes to cross
// half its circumference, pi (d/2) sqrt(rho/G) / (0.1631 nu + 0.8766), G = E/(2(1 + nu))
// (Li, Xu & Thornton 2005; docs/references.md).
double rayleigh_time(const Material& m, double d);

// One size of one material: the smallest or the largest grain of it.
struct GrainTimes {
  int material = 0;
  double diameter = 0;        // m
  double contact_time = 0;    // s, against an equal grain at the impact speed
  double rayleigh_time = 0;   // s
  double terminal_speed = 0;  // m/s, with a fluid (0 otherwise)
  double relaxation_time = 0; // s, the drag's at the terminal speed; infinite without drag
};

struct TimeScales {
  double impact_speed = 0;     // m/s, the representative approach speed of a collision
  std::string impact_reason;   // where it comes from
  std::vector<GrainTimes> grains;
  double shortest_contact = 0;       // s, over every pair of the grains above and every wall
  std::string shortest_contact_what; // which pair, and its normal model
  bool contact_resolution_matters = true;  // false with models P and F (exact whatever dt)
  double deepest_overlap = 0;        // the largest peak overlap / smaller diameter at the impact speed
  std::string deepest_overlap_what;  // which pair, and its normal model
  double shortest_relaxation = 0;    // s, infinite without a fluid's drag
  double suggested_dt = 0;           // s
  std::string suggestion;            // how suggested_dt follows from the rules
  int needed_level = 0;              // block steps: the finest level the rules need
  bool safe = true;                  // dt <= suggested_dt (block steps: needed_level <= levels)
  std::int64_t steps = 0;            // round(duration / dt)
  std::vector<std::string> warnings; // a dt that cannot resolve the stiffest contact or the drag
};

// The time scales of the grains `world` holds now and of those an inflow source will bring.
TimeScales time_scales(const Scenario& scenario, const World& world);

// The wall time of the run from a short sample: the world is stepped (at most
// `max_steps` steps, stopping once `budget_s` seconds have passed) and the time per step
// is multiplied by the run's steps. That is an estimate (within about 2x) only while the
// grains stay as they start, packed or apart: a step's cost follows the grains present, their
// contacts and how often their neighbour lists are rebuilt. When the run will change them
// (an inflow brings its grains; grains that start apart fall and pack, a packed bed costing
// several times more a step, and rebuild their lists as they fall), `cannot` says so and the
// sample's cost is a lower bound.
struct WallTimeEstimate {
  std::int64_t sampled_steps = 0;
  double sample_seconds = 0;      // the sampled steps alone, without the first force evaluation
  double run_seconds = 0;         // the sample's cost per step times the run's steps
  std::size_t particles = 0;      // present in the sample
  double contacts_per_grain = 0;  // touching contacts (pairs and walls) per grain after the sample
  std::string cannot;             // why run_seconds is only a lower bound; empty when it is the estimate
  std::string failure;            // the sample stopped with a numerical failure (the message)
};
WallTimeEstimate estimate_wall_time(const Scenario& scenario, World world, std::int64_t max_steps, double budget_s);

}  // namespace tsubu
