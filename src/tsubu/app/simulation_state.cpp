#include "tsubu/app/simulation_state.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tsubu/core/error.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/version.hpp"

namespace tsubu {

void store_simulation(const Scenario& sc, const Simulation& sim, Checkpoint& c) {
  c.engine_version = kVersion;
  c.scenario_path = sc.file;
  c.scenario_text = sc.text;
  c.overrides = sc.overrides;
  c.scenario_hash = sc.hash;
  const World& world = sim.world();
  c.step = world.step;
  c.time = world.time;
  c.dt = world.dt;
  c.counters = sim.forces().counters();
  if (const BlockHermite* b = sim.block()) {
    c.block.present = true;
    c.block.state = b->state();
    c.block.list_positions = b->list_positions();
    c.block.list_reach = b->list_reach();
    c.block.lists_stale = b->lists_stale();
    c.block.stats = b->stats();
  }
  c.wall_points.clear();
  c.wall_velocities.clear();
  for (const Wall& w : world.walls) c.wall_points.push_back(w.point), c.wall_velocities.push_back(w.velocity);
  if (const InflowFeed* inflow = sim.inflow()) c.inflow = {true, inflow->first_id(), inflow->state()};
  if (const Outflow* outflow = sim.outflow()) c.departed = {true, outflow->totals()};
}

Simulation new_simulation(const Scenario& sc) {
  Simulation sim(build_world(sc), build_model(sc), sc.integrator, sc.block_steps);  // bad input is reported here
  if (const ParticleSource* src = inflow_source(sc))
    sim.feed(InflowFeed(sc, *src, static_cast<std::int64_t>(sim.world().particles.size())));
  return sim;
}

void with_state_lent(Simulation& sim, Checkpoint& c, const std::function<void()>& write) {
  World& world = sim.world();
  auto lend = [&] {
    std::swap(c.particles, world.particles);
    std::swap(c.pair_contacts, world.contacts.pairs());
    std::swap(c.wall_contacts, world.contacts.walls());
  };
  lend();
  struct GiveBack {
    decltype(lend)& back;
    ~GiveBack() { back(); }
  } give_back{lend};
  write();
}

Checkpoint read_newest_checkpoint(const std::filesystem::path& dir, std::filesystem::path& used,
                                  const CheckpointChoice& choice) {
  namespace fs = std::filesystem;
  const auto files = list_checkpoints(dir);
  if (files.empty())
    throw std::runtime_error("no checkpoint in " + dir.string() + " (step_*.tsbk): nothing to " + choice.purpose +
                             (fs::exists(dir) ? ""
                                              : "; a run writes checkpoints only when [output] checkpoint_every_steps or "
                                                "checkpoint_every_seconds is above 0"));
  std::ostringstream later;  // the times of the valid checkpoints after choice.at, for the error
  for (const auto& f : files) {
    try {
      Checkpoint c = read_checkpoint(f);
      if (choice.at && c.time > *choice.at) {
        later << (later.tellp() > 0 ? ", " : "") << c.time;
        continue;
      }
      used = f;
      return c;
    } catch (const CheckpointError& e) {
      std::error_code ec;
      if (choice.rename_damaged) fs::rename(f, f.string() + ".damaged", ec);  // kept for inspection
      std::fprintf(stderr, "tsubu: checkpoint %s is unusable (%s); %s\n", f.string().c_str(), e.what(),
                   choice.rename_damaged ? "renamed to *.damaged, trying the previous one" : "skipped");
    }
  }
  if (later.tellp() == 0) throw std::runtime_error("no valid checkpoint in " + dir.string() + ": nothing to " + choice.purpose);
  std::ostringstream time;
  time << *choice.at;
  throw UsageError("--at " + time.str() + ": no checkpoint at or before this time; " + dir.string() +
                   " holds checkpoints at t = " + later.str() + " s (the last two of the run and its end are kept)");
}

Scenario scenario_of(const Checkpoint& c, const std::filesystem::path& used) {
  Scenario sc = load_scenario_text(c.scenario_text, c.scenario_path, c.overrides, false);
  if (sc.hash != c.scenario_hash || sc.dt != c.dt)
    throw std::runtime_error(used.string() + " does not match the scenario it stores (hash or dt differ)");
  return sc;
}

Simulation restore_simulation(const Scenario& sc, Checkpoint& c, const std::filesystem::path& used) {
  Simulation sim(world_of_checkpoint(sc, c, used), build_model(sc), sc.integrator, sc.block_steps);
  if (sim.block()) {
    if (!c.block.present || c.block.state.size() != sim.world().particles.size())
      throw std::runtime_error(used.string() + ": a block-step run's checkpoint without a complete block-step state");
    sim.block()->resume(sim.world(), sim.forces(), std::move(c.block.state), std::move(c.block.list_positions),
                        std::move(c.block.list_reach), c.block.lists_stale, c.block.stats);
  } else if (c.block.present) {
    throw std::runtime_error(used.string() + ": holds a block-step state, but the scenario is not a block-step run");
  }
  sim.forces().restore_counters(c.counters);
  if (const ParticleSource* src = inflow_source(sc)) {
    if (!c.inflow.present) throw std::runtime_error(used.string() + ": lacks the state of the scenario's inflow");
    InflowFeed inflow(sc, *src, c.inflow.first_id);
    inflow.restore(c.inflow.state);
    sim.feed(std::move(inflow));
  }
  if (Outflow* outflow = sim.outflow()) {
    if (!c.departed.present) throw std::runtime_error(used.string() + ": lacks the totals of the grains gone through the open faces");
    outflow->restore(c.departed.totals);
  }
  return sim;
}

}  // namespace tsubu
