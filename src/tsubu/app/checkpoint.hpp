// Checkpoints: everything a run needs to continue bit-identically, in a versioned binary
// file with a checksum, written atomically into OUT/checkpoint/ (docs/reliability.md).
#pragma once
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/analysis/energy_watch.hpp"
#include "tsubu/integrate/block_hermite.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/outflow.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// The output files' state at the checkpoint: a resumed run truncates series.csv, track.csv
// and outflow.csv to these sizes and continues the frame numbering and the .pvd index.
struct OutputState {
  std::int64_t frame = 0;                            // next frame number
  std::vector<std::pair<double, std::string>> pvd;  // (time, file) of the frames so far
  std::uint64_t series_bytes = 0, track_bytes = 0;
  std::uint64_t outflow_bytes = 0;  // stored in the section of the departed grains
};

struct Checkpoint {
  std::string engine_version;
  std::string run_id;                        // of the outputs it belongs to (io/output_dir.hpp)
  std::string scenario_path, scenario_text;  // the scenario as read, and where from
  std::vector<std::string> overrides;        // --set values, in order
  std::uint64_t scenario_hash = 0;
  std::int64_t step = 0;
  double time = 0, dt = 0;
  ForceField::Counters counters;
  double wall_seconds = 0;                      // run time so far, over all sessions
  OutputState output;
  Particles particles;  // every array, force/torque/contact_count of the last evaluation included
  std::vector<Contact> pair_contacts, wall_contacts;  // with their histories
  std::vector<Vec3> wall_points, wall_velocities;     // moving walls' planes, per wall
  EnergyWatch::State energy_watch;                    // the energy-growth check's reference
  // Block-step Hermite runs only (an optional section at the end of the payload): the
  // integrator's per-particle state, where and how far its lists were built, its counters.
  struct BlockSteps {
    bool present = false;
    HermiteState state;
    std::vector<Vec3> list_positions;
    std::vector<double> list_reach;
    bool lists_stale = false;
    BlockStepStats stats;
  } block;
  // Runs with an inflow only (an optional section after the block steps'): the first id of
  // its grains and its stream's state (encode_inflow_state).
  struct Inflow {
    bool present = false;
    std::int64_t first_id = 0;
    std::string state;
  } inflow;
  // What the run records across its sessions (an optional section after the inflow's, absent
  // in the checkpoints of older tsubus): each [[particles]] source's ids (run.json's sources)
  // and its stepping loops' totals (loop_time_s, particle_steps_per_second).
  struct Record {
    bool present = false;
    std::vector<std::pair<std::int64_t, std::int64_t>> source_ids;  // World::source_ids
    double loop_seconds = 0;       // the stepping loops of the sessions counted
    std::int64_t loop_steps = 0;   // their steps
    std::int64_t loop_sessions = 0;  // the sessions these cover
  } record;
  // Runs with open faces only (an optional section after the record): the totals of the
  // grains gone through them (Outflow::Totals), and output.outflow_bytes.
  struct Departed {
    bool present = false;
    Outflow::Totals totals;
  } departed;
};

// A checkpoint file that cannot be used (missing, truncated, corrupted, other version).
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// 2: the run id; 3: a pair's history is stored as seen from its particle with the smaller id
// (ContactList), not from the smaller index; 4: block steps store the steps chosen by rule
// (BlockStepStats::set_by_own, set_by_cluster); 5: particles in the order of their ids and
// only the touching contacts (no touching flag), so that the bytes do not depend on the
// particles' numbering or on when the lists were built; 6: the contacts' rolling spring;
// 7: the particle force evaluations (ForceField::Counters).
inline constexpr std::uint32_t kCheckpointVersion = 7;

// The file's bytes: a 32-byte header (magic "TSUBUCKP", version, byte-order mark, payload
// size, FNV-1a 64 of the payload) and the payload. The particles of c may be in any order
// and its lists may hold entries that do not touch: the file holds the particles by id and
// the touching contacts only (a checkpoint decoded is in that order).
std::string encode_checkpoint(const Checkpoint& c);
// Throws CheckpointError naming what is wrong.
Checkpoint decode_checkpoint(const std::string& bytes);

// The checkpoint files of a folder (step_<step>.tsbk), newest (highest step) first.
std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& dir);
// Writes step_<step>.tsbk into dir atomically, then removes all but the newest `keep`
// checkpoints and any leftover temporary files. Returns the file written.
std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const Checkpoint& c, int keep = 2);
Checkpoint read_checkpoint(const std::filesystem::path& file);

// The world of checkpoint c (read from `file`, named in errors) under its scenario sc: the
// particles and contact lists are moved out of c; the walls stand where they were.
World world_of_checkpoint(const Scenario& sc, Checkpoint& c, const std::filesystem::path& file);

}  // namespace tsubu
