#include "tsubu/app/export.hpp"

#include <cstdio>
#include <string>

#include "tsubu/app/simulation_state.hpp"
#include "tsubu/forces/force_field.hpp"
#include "tsubu/io/contact_network.hpp"
#include "tsubu/io/particle_csv.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

namespace fs = std::filesystem;

ExportedState export_checkpoint(const fs::path& out_dir, std::optional<double> at, const fs::path& to) {
  fs::path used;
  Checkpoint c =
      read_newest_checkpoint(out_dir / "checkpoint", used, {.purpose = "export", .at = at, .rename_damaged = false});
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
  const Model model = build_model(sc);
  ForceField forces(model);
  forces.compute(world);
  write_contacts_csv(out.contacts.string(), contact_network(world, forces.touching_contacts(world)), world.time,
                     forces.resists_rolling());
  return out;
}

}  // namespace tsubu
