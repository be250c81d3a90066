#include "tsubu/app/export.hpp"

#include <cstdio>
#include <sstream>
#include <string>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/contact/force_field.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/io/contact_network.hpp"
#include "tsubu/io/particle_csv.hpp"
#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

namespace fs = std::filesystem;

ExportedState export_checkpoint(const fs::path& out_dir, std::optional<double> at, const fs::path& to) {
  const fs::path dir = out_dir / "checkpoint";
  const auto files = list_checkpoints(dir);
  if (files.empty()) throw std::runtime_error("no checkpoint in " + dir.string() + " (step_*.tsbk): nothing to export");
  Checkpoint c;
  fs::path used;
  std::ostringstream seen;  // the times of the valid checkpoints, for the error
  for (const auto& f : files) {  // newest first
    try {
      Checkpoint candidate = read_checkpoint(f);
      seen << (seen.tellp() > 0 ? ", " : "") << candidate.time;
      if (at && candidate.time > *at) continue;
      c = std::move(candidate);
      used = f;
      break;
    } catch (const CheckpointError& e) {
      std::fprintf(stderr, "tsubu: checkpoint %s is unusable (%s); skipped\n", f.string().c_str(), e.what());
    }
  }
  if (used.empty() && seen.tellp() == 0) throw std::runtime_error("no valid checkpoint in " + dir.string() + ": nothing to export");
  if (used.empty()) {
    std::ostringstream time;
    time << *at;
    throw UsageError("--at " + time.str() + ": no checkpoint at or before this time; " + dir.string() +
                     " holds checkpoints at t = " + seen.str() + " s (the last two of the run and its end are kept)");
  }
  const Scenario sc = load_scenario_text(c.scenario_text, c.scenario_path, c.overrides, false);
  World world = world_of_checkpoint(sc, c, used);
  ExportedState out{used, {}, {}, c.step, c.time};
  char suffix[40];
  std::snprintf(suffix, sizeof suffix, "_%012lld.csv", static_cast<long long>(c.step));
  fs::create_directories(to);
  out.particles = to / ("particles" + std::string(suffix));
  out.contacts = to / ("contacts" + std::string(suffix));
  write_particles_csv(out.particles.string(), world.particles);
  // The contacts' forces are not stored: one evaluation of the checkpoint's state gives them,
  // as the first step of a resume sees it (after the particles are written: models P and F
  // move positions when they evaluate).
  ForceField forces;
  forces.compute(world);
  write_contacts_csv(out.contacts.string(), contact_network(world, forces.touching_contacts(world)), world.time);
  return out;
}

}  // namespace tsubu
