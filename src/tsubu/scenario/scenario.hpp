// A validated scenario: plain data, every value checked, every name resolved to an index.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/contact/law.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/core/size_distribution.hpp"
#include "tsubu/scenario/deposit_rules.hpp"
#include "tsubu/fluid/fluid.hpp"
#include "tsubu/integrate/block_hermite.hpp"
#include "tsubu/integrate/integrators.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

// Where an insertion source places its grains: a box [lower, upper], or a cylinder of
// `radius` about the axis from `point` (the centre of its base) along `axis` for `length`.
struct InsertionRegion {
  enum class Shape { box, cylinder };
  Shape shape = Shape::box;
  Vec3 lower, upper;  // box, m
  Vec3 point, axis;   // cylinder
  double radius = 0, length = 0;  // cylinder, m
};

struct ParticleSource {
  enum class Kind { csv, file, lattice, random, inflow, insertion };
  Kind kind = Kind::csv;
  SourceLocation where;                 // the [[particles]] table
  std::vector<SourceLocation> key_where;  // each of its keys: its line or the --set that gave it
  // Where `key` of the table came from, for errors found after loading.
  SourceLocation at(const std::string& key) const {
    for (const SourceLocation& k : key_where)
      if (k.key == where.key + "." + key) return k;
    return {where.file, where.line, where.key + "." + key};
  }
  int material = 0;
  std::string file;                // csv, file: path (resolved against the scenario's folder)
  double overlap_tolerance = 0.01; // csv, file: largest allowed overlap / smaller diameter
  Vec3 lower, upper;               // lattice, random: region, m
  double diameter = 0;             // lattice, m
  double spacing = 0;              // lattice, m
  double solid_fraction = 0;       // random; inflow: phi_0 of the virtual column
  SizeDistribution sizes;          // random, inflow, insertion
  Vec3 velocity;                   // lattice, random, insertion: initial velocity, m/s
  // inflow (docs/sedimentation.md): grains arrive during the run, none at the start
  double entry_height = 0;    // z_c, m
  double fall_speed = 0;      // u_r, m/s: as given, or Rubey's speed of the largest grain
  double mass_limit = 0;      // kg, 0: none (also insertion)
  double omega_star_rms = 0;  // Omega*_rms of the initial spin
  // insertion (docs/scenario.md): grains placed in a region during the run, none at the start
  InsertionRegion region;
  double mass_rate = 0;  // kg/s; 0: the whole mass_limit at `start`
  double start = 0;      // s
};

struct PairContactSpec {
  int a = 0, b = 0;
  ContactSpec spec;
};

struct OutputSpec {
  std::string dir;             // empty: out/<name>
  double vtk_interval = 0;     // s, 0 = no frames
  bool contacts = true;        // the contact network with every frame
  double series_interval = 0;  // s
  std::vector<std::int64_t> track;  // particle ids written to track.csv
  double track_interval = 0;        // s, 0 = every step
  std::int64_t checkpoint_every_steps = 0;  // 0: none by step count
  double checkpoint_every_seconds = 600;    // wall-clock s, 0: none by time
  SourceLocation where;             // the [output] table, for errors found at run time
};

struct AnalysisSpec {
  enum class Kind { solid_fraction, coordination, deposit_height, porosity, segregation, kinetic_energy, profiles };
  Kind kind = Kind::solid_fraction;
  std::string name;
  double z_low = 0, z_high = 0;  // m, the measured slab
  bool slice_rule = false;       // deposit_height: rule = "slices" (the paper's); false: "surface"
  SliceRule slices;              // deposit_height, rule = "slices"
  SurfaceRule surface;           // deposit_height, rule = "surface"
  long points = 65536;           // porosity: Monte Carlo points
  std::uint64_t seed = 1;        // porosity: of the points
  double small_diameter = 0;     // segregation: grains below it are small, m
  int profile_slices = 0;        // profiles: slices of equal thickness over [z_low, z_high]
  std::vector<double> class_edges;  // profiles: size class i is class_edges[i] <= d < class_edges[i+1], m
};

// A [[stop]] condition: the run ends (status ok) at the first series.csv row where the
// analysis result `when` has reached `limit` from below (at_least) or from above (at_most).
struct StopSpec {
  std::string when;       // a result name of one of the [[analyses]]
  bool at_least = true;   // value >= limit; false: value <= limit
  double limit = 0;
  double after = 0;       // s: not checked before this time
  bool after_inflow = false;  // not checked before the inflow has released its last grain (its mass_limit)
};

// [parallel]: how a run split among processes (mpirun -np N, N > 1) cuts its box.
struct ParallelSpec {
  std::array<int, 3> counts{0, 0, 0};  // subdomains along x, y, z; 0: an automatic count (RankGrid)
  bool balance = true;                 // the cuts follow the work ("work") or stay evenly spaced ("none")
  SourceLocation where;                // parallel.counts, checked against the number of processes at the start
};

struct Scenario {
  std::string file, name;
  std::uint64_t hash = 0;  // FNV-1a of the scenario text and overrides
  std::string text;                    // the scenario file as read, for checkpoints
  std::vector<std::string> overrides;  // the --set values, in order
  double duration = 0, dt = 0;
  Integrator integrator = Integrator::velocity_verlet;
  BlockStepRules block_steps;  // [simulation.block_steps], integrator = "block_hermite"
  Vec3 gravity{0, 0, -9.81};
  Fluid fluid;  // [fluid]; absent: no fluid
  SourceLocation fluid_where;  // fluid.hindered_ball_ratio, for checks made once the particles exist
  std::uint64_t seed = 1;
  double overlap_limit = 0.1;
  double energy_growth_limit = 0.5;  // see EnergyWatch; 0: off
  double skin = 0;  // m, neighbour-list margin; 0: a tenth of the smallest diameter
  Domain domain;
  SourceLocation domain_where;  // the [domain] table, for checks made once the particles exist
  std::vector<Material> materials;
  ContactSpec default_contact;
  std::vector<PairContactSpec> pair_contacts;
  std::vector<Wall> walls;
  std::vector<ParticleSource> sources;
  OutputSpec output;
  std::vector<AnalysisSpec> analyses;  // in the order of the file
  std::vector<StopSpec> stops;         // [[stop]]
  SearchSpec search{SearchSpec::Method::cell, 0, 1000};  // [search]: contact search method, spatial sort every 1000 steps
  ParallelSpec parallel;
};

// Reads and validates a scenario. `overrides` are "key.path=value" strings (TOML values)
// applied before validation. Throws InputError.
Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides = {});

// The same from the text of a scenario (`path` names it in messages and anchors relative CSV
// paths). With particle_files = false, CSV sources are not required to exist (tsubu resume
// takes the particles from a checkpoint).
Scenario load_scenario_text(const std::string& text, const std::string& path,
                            const std::vector<std::string>& overrides, bool particle_files = true);

// One [[analyses]] entry given as TOML text (type = ..., name, z_range, ...), read and checked
// as in a scenario file, with sc's box, seed and sources for its defaults; `origin` names the
// text in messages. For drivers that ask for measurements on the current state (Python).
AnalysisSpec load_analysis_text(const Scenario& sc, const std::string& text, const std::string& origin);

}  // namespace tsubu
