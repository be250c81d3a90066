// Runs split among processes (ranks/decomposition.hpp), and block steps shared among them
// (ranks/shared_block_steps.hpp), end with the bits of one process.
// Each test runs under `mpirun -np N` (tests/CMakeLists.txt: N = 1 to 4, one and two threads
// per process); process 0 also runs the scenario alone and compares the states a checkpoint
// stores (every particle array, the touching contacts and their histories, the walls) and
// the outputs that read the contacts' forces (gathered with them on process 0).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/app/observed_run.hpp"
#include "tsubu/app/simulation_state.hpp"
#include "tsubu/io/contact_network.hpp"
#include "tsubu/ranks/decomposition.hpp"
#include "tsubu/ranks/shared_block_steps.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {
namespace {

// The outputs of one process that read the last evaluation's contacts: the totals of the
// time series, every wall's load and the contact network, as bytes.
std::string contact_outputs_of(const World& w, const ForceField& forces) {
  std::string out;
  const auto put = [&](const auto& v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const ContactTotals t = forces.totals(w);
  put(t.contacts), put(t.elastic_energy), put(t.max_overlap_ratio);
  for (std::size_t k = 0; k < w.walls.size(); ++k) put(forces.wall_load(w, k));
  for (const NetworkContact& c : contact_network(w, forces.touching_contacts(w))) {
    put(c.id_i), put(c.id_j), put(c.wall), put(c.centre_i), put(c.point), put(c.branch), put(c.normal_force);
    put(c.tangential_force), put(c.overlap), put(c.history.xi), put(c.history.normal);
  }
  return out;
}

// The state a checkpoint stores of a world (particles by id, touching contacts), as bytes.
std::string state_of(const World& w) {
  Checkpoint c;
  c.particles = w.particles;
  c.pair_contacts = w.contacts.pairs();
  c.wall_contacts = w.contacts.walls();
  c.step = w.step;
  c.time = w.time;
  for (const Wall& wall : w.walls) c.wall_points.push_back(wall.point), c.wall_velocities.push_back(wall.velocity);
  return encode_checkpoint(c);
}

struct Case {
  std::string scenario;  // under the source folder
  std::vector<std::string> overrides;
  std::array<int, 3> counts{};  // the grid of subdomains; automatic when zero
  double grid_top = 0;          // > 0: the grid spans the box only up to this height (the bed)
  bool balance = true;          // the cuts follow the work ([parallel] balance)
};

// The scenario run to its end split among all processes and, on process 0, alone.
void expect_same_bits(const Case& c) {
  const Communicator& comm = Communicator::world();
  const Scenario sc = load_scenario(std::string(TSUBU_SOURCE_DIR) + "/" + c.scenario, c.overrides);
  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  Simulation split = new_simulation(sc);  // with the scenario's inflow
  Domain cut = split.world().domain;
  if (c.grid_top > 0) cut.upper.z = c.grid_top;
  const std::unique_ptr<Decomposition> split_run = split_among_processes(comm, split, cut, ParallelSpec{c.counts, c.balance});
  const Decomposition& decomposition = *split_run;
  split.start();
  split.advance_to(steps);
  const bool ghosts = comm.any(split.world().ghosts > 0);
  const double most_builds = comm.max(static_cast<double>(split.forces().rebuilds()));
  Decomposition::Gathered all = decomposition.gathered(split.world(), split.forces());
  if (comm.rank() != 0) return;
  const std::array<int, 3>& g = decomposition.grid().counts();
  SCOPED_TRACE(c.scenario + " on " + std::to_string(comm.size()) + " processes (" + std::to_string(g[0]) + " x " +
               std::to_string(g[1]) + " x " + std::to_string(g[2]) + "), " + std::to_string(omp_get_max_threads()) + " threads");
  if (comm.size() > 1) {
    EXPECT_TRUE(ghosts) << "no process held a copy of another's particle";
    EXPECT_GT(decomposition.arrangements(), 2u) << "the particles were never handed over";
  }
  Simulation alone = new_simulation(sc);
  alone.start();
  alone.advance_to(steps);
  // A split run builds its lists at most about as often as one process: at its hand-overs
  // (decided by the same skin) and when a ghost has moved half a skin.
  EXPECT_LE(most_builds, 1.5 * static_cast<double>(alone.forces().rebuilds()) + 10) << "lists built far more often than alone";
  ASSERT_EQ(all.world.particles.size(), alone.world().particles.size());
  EXPECT_TRUE(state_of(all.world) == state_of(alone.world())) << "the split run's state differs from one process's";
  if (const Outflow* gone = alone.outflow()) {  // every process records every departure
    EXPECT_GT(gone->totals().count, 0);
    EXPECT_EQ(split.outflow()->totals().count, gone->totals().count);
    EXPECT_EQ(split.outflow()->totals().mass, gone->totals().mass);
  }
  ForceField view(alone.model());  // the gathered contacts' outputs, as one process writes them
  view.adopt_results(std::move(all.pair_results), std::move(all.wall_results));
  EXPECT_GT(view.totals(all.world).contacts, 0u);
  EXPECT_TRUE(contact_outputs_of(all.world, view) == contact_outputs_of(alone.world(), alone.forces()))
      << "the split run's contact totals, wall loads or contact network differ from one process's";
}

// Grains poured onto a floor in a box periodic along x and y, velocity Verlet, Hertz with
// Mindlin's friction, the subdomains stacked through the forming bed: grains fall through
// them and are handed over with their contacts; contacts cross every cut.
TEST(Decomposition, APouredBedCutThroughItsHeight) {
  const int n = Communicator::world().size();
  expect_same_bits({"tests/scenarios/settle_mono.toml", {"simulation.duration=0.1"}, {1, 1, n}, 0.02});
}

// Grains poured from the lowest quarter of the box only, cut through the height of the whole
// box: the cuts follow the work down into the grains. The grains poured from the whole box on
// the even cuts of [parallel] balance = "none" give the same bits too.
TEST(Decomposition, CutsThatFollowTheWorkKeepTheBits) {
  const Communicator& comm = Communicator::world();
  const int n = comm.size();
  for (const bool balance : {true, false}) {
    std::vector<std::string> overrides = {"simulation.duration=0.05"};
    if (balance) overrides.push_back("particles.0.upper=[0.016, 0.016, 0.04]");
    expect_same_bits({"tests/scenarios/settle_mono.toml", overrides, {1, 1, n}, 0, balance});
    const Scenario sc = load_scenario(std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/settle_mono.toml", overrides);
    Simulation sim = new_simulation(sc);
    const auto split = split_among_processes(comm, sim, sim.world().domain, ParallelSpec{{1, 1, n}, balance});
    const std::vector<double>& cuts = split->grid().cuts(2);
    for (int s = 1; s < n; ++s) {
      if (balance) EXPECT_LT(cuts[static_cast<std::size_t>(s)], 0.04) << "cut " << s << " did not move into the grains";
      else EXPECT_NEAR(cuts[static_cast<std::size_t>(s)], 0.16 * s / n, 1e-12) << "balance = \"none\" moved cut " << s;
    }
  }
}

// The bed cut across its periodic sides (2 x 2 x 1, or n x 1 x 1): ghosts across the periodic
// boundaries; with two processes along an axis, both neighbours are one process.
TEST(Decomposition, CutsAcrossPeriodicSidesKeepTheBits) {
  const int n = Communicator::world().size();
  expect_same_bits({"tests/scenarios/settle_mono.toml", {"simulation.duration=0.05"}, n == 4 ? std::array{2, 2, 1} : std::array{n, 1, 1}});
}

// Symplectic Euler with model P (a position correction on a contact's first step) and
// Coulomb springs.
TEST(Decomposition, ModelPWithItsPositionCorrectionKeepsTheBits) {
  expect_same_bits({"tests/scenarios/checkpoint_model_p.toml", {"simulation.duration=0.04"}});
}

// Moving walls (the contact network scenario's) and the Hooke/Hysteresis piston, cut along x.
TEST(Decomposition, MovingWallsKeepTheBits) {
  const int n = Communicator::world().size();
  expect_same_bits({"tests/scenarios/contact_network.toml", {"simulation.duration=0.05"}, {n, 1, 1}});
  expect_same_bits({"examples/piston-hysteresis.toml", {"simulation.duration=0.05"}, {n, 1, 1}});
}

// A polydisperse bed on the multi-level grid and on the cell grid, cut along x: the ghost
// layer is as wide as the largest grain's reach.
TEST(Decomposition, APolydisperseBedKeepsTheBitsOnBothSearches) {
  const int n = Communicator::world().size();
  expect_same_bits({"tests/scenarios/poly_search.toml", {}, {n, 1, 1}});
  expect_same_bits({"tests/scenarios/poly_search.toml", {"search.method=\"cell\""}, {n, 1, 1}});
}

// The poured bed in water with hindered settling, cut through its height: each grain's drag
// reads the solid fraction in a ball of 3 radii around it, whose grains lie up to 4 r_max
// away, across the cuts (the ghost layer is as wide as that reach, not only the contacts').
TEST(Decomposition, HinderedSettlingKeepsTheBits) {
  const int n = Communicator::world().size();
  expect_same_bits({"tests/scenarios/settle_mono.toml",
                    {"simulation.duration=0.04", "fluid.density=1000", "fluid.kinematic_viscosity=1e-6",
                     "fluid.hindered_settling=true"},
                    {1, 1, n}});
}

// Grains rain from the inflow into water onto a deposit, cut through its height, and (with
// hindered settling) enter a box cut across x; grains delayed at a crowded entry: every
// process admits the same grains (the entry plane's verdicts agreed among the processes) and
// keeps those in its subdomain; with hindered settling too.
TEST(Decomposition, TheInflowKeepsTheBits) {
  const int n = Communicator::world().size();
  expect_same_bits({"tests/scenarios/inflow_small.toml", {"simulation.duration=0.3"}, {1, 1, n}, 0.01});  // cut through the deposit
  // A floor just below the entry plane: grains rest where the next ones would enter, which
  // wait (delayed) until their place is free; the box cut across x.
  expect_same_bits({"tests/scenarios/inflow_small.toml",
                    {"simulation.duration=0.1", "walls=[{point=[0, 0, 0.0275], normal=[0, 0, 1], material=\"quartz\"}]"},
                    {n, 1, 1}});
  expect_same_bits({"tests/scenarios/sediment_inflow.toml",
                    {"simulation.duration=0.02", "simulation.dt=1e-6", "fluid.hindered_settling=true"}, {n, 1, 1}});
}

// Grains slide down the chute and leave through its open end, the box cut along the chute:
// the processes agree on every grain gone before each evaluation, drop it and its copies and
// record it alike. Grains inserted into a bin at a mass rate, the bin cut through its
// height: every process places the same grains (their places' verdicts agreed) and keeps
// those in its subdomain.
TEST(Decomposition, OpenFacesAndInsertionKeepTheBits) {
  const int n = Communicator::world().size();
  // The grains start on the chute's lower half, so that they leave from the first steps on.
  expect_same_bits({"tests/scenarios/chute_open.toml",
                    {"simulation.duration=0.05", "particles.0.lower=[0.02, 0, 0]", "particles.0.upper=[0.04, 0.008, 0.03]"},
                    {n, 1, 1}});
  expect_same_bits({"tests/scenarios/insertion_bin.toml", {"simulation.duration=0.12"}, {1, 1, n}});  // contacts from 0.09 s
}

// Block steps shared among the processes (ranks/shared_block_steps.hpp): every process holds
// the whole run and ends each step with one process's bits, the contacts' outputs and the
// stepper's statistics included. A settling lattice whose free grains are all active at the
// ends of dt (every parallel loop engages) and whose lower layers step finer on the floor;
// the rain of grains into water, with its inflow and frequent renumbering; a turning mesh.
// block_run_bytes: the state, the contacts' outputs and the block steps' counts of a run.
std::string block_run_bytes(const Simulation& sim) {
  const BlockStepStats& stats = sim.block()->stats();
  return state_of(sim.world()) + contact_outputs_of(sim.world(), sim.forces()) + std::to_string(stats.block_times) +
         " " + std::to_string(stats.wakes) + " " + std::to_string(sim.block()->particle_evaluations()) + " " +
         std::to_string(sim.forces().evaluations());
}

TEST(SharedBlockSteps, EndWithTheBitsOfOneProcessOnEveryProcess) {
  const Communicator& comm = Communicator::world();
  for (const auto& [scenario, overrides] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"tests/scenarios/block_threads.toml", {"simulation.duration=0.003"}},
           {"tests/scenarios/rain_small.toml", {"simulation.duration=0.15", "search.sort_every=3"}},
           {"tests/scenarios/mesh_mixer.toml", {"simulation.duration=0.01", "simulation.integrator=\"block_hermite\""}}}) {
    const Scenario sc = load_scenario(std::string(TSUBU_SOURCE_DIR) + "/" + scenario, overrides);
    const std::int64_t steps = std::llround(sc.duration / sc.dt);
    Simulation shared = new_simulation(sc);
    const std::unique_ptr<ActiveShare> share = share_block_steps(comm, shared);
    shared.start();
    shared.advance_to(steps);
    const std::vector<std::string> every = comm.gather(block_run_bytes(shared));
    if (comm.rank() != 0) continue;
    SCOPED_TRACE(scenario + " on " + std::to_string(comm.size()) + " processes, " + std::to_string(omp_get_max_threads()) +
                 " threads");
    Simulation alone = new_simulation(sc);
    alone.start();
    alone.advance_to(steps);
    const std::string expected = block_run_bytes(alone);
    EXPECT_GT(alone.block()->stats().block_times, static_cast<std::uint64_t>(steps)) << "no step was divided";
    for (std::size_t r = 0; r < every.size(); ++r)
      EXPECT_TRUE(every[r] == expected) << "process " << r << "'s state, contacts or counts differ from one process's";
  }
}

// A checkpoint's bytes of a run at its current step (the force counters, which count each
// process's own evaluations, left out).
std::string checkpoint_bytes(const Scenario& sc, Simulation& sim) {
  Checkpoint c;
  store_simulation(sc, sim, c);
  c.counters = {};
  std::string bytes;
  with_state_lent(sim, c, [&] { bytes = encode_checkpoint(c); });
  return bytes;
}

// The checkpoint of a split run, written from its state gathered on process 0, is byte for
// byte the checkpoint of one process at the same step; and a run resumed from a checkpoint
// split among the processes (each reads it whole and keeps its part) ends with the bits of
// one uninterrupted process. Together: a checkpoint written by any number of processes
// resumes on any number.
TEST(Decomposition, ACheckpointOfASplitRunResumesOnAnyNumberOfProcesses) {
  const Communicator& comm = Communicator::world();
  const int n = comm.size();
  const Scenario sc =
      load_scenario(std::string(TSUBU_SOURCE_DIR) + "/tests/scenarios/settle_mono.toml", {"simulation.duration=0.1"});
  const std::int64_t steps = std::llround(sc.duration / sc.dt), half = steps / 2;
  const auto split_run = [&](Simulation& sim) {
    Domain cut = sim.world().domain;
    cut.upper.z = 0.02;
    return split_among_processes(comm, sim, cut, ParallelSpec{{1, 1, n}});
  };
  Simulation alone = new_simulation(sc);  // on every process: each reads the checkpoint whole
  alone.start();
  alone.advance_to(half);
  const std::string checkpoint = checkpoint_bytes(sc, alone);

  Simulation split = new_simulation(sc);
  const auto first = split_run(split);
  split.start();
  split.advance_to(half);
  Decomposition::Gathered at_half = first->gathered(split.world(), split.forces());
  if (comm.rank() == 0) {
    Simulation gathered(std::move(at_half.world), build_model(sc), sc.integrator, sc.block_steps);
    EXPECT_TRUE(checkpoint_bytes(sc, gathered) == checkpoint) << "a split run's checkpoint differs from one process's";
  }

  Checkpoint c = decode_checkpoint(checkpoint);
  Simulation resumed = restore_simulation(sc, c, "checkpoint");
  const auto second = split_run(resumed);
  resumed.advance_to(steps);
  Decomposition::Gathered end = second->gathered(resumed.world(), resumed.forces());
  alone.advance_to(steps);
  if (comm.rank() != 0) return;
  EXPECT_TRUE(state_of(end.world) == state_of(alone.world())) << "the resumed split run's state differs from one process's";
  ForceField view(alone.model());
  view.adopt_results(std::move(end.pair_results), std::move(end.wall_results));
  EXPECT_TRUE(contact_outputs_of(end.world, view) == contact_outputs_of(alone.world(), alone.forces()));
}

}  // namespace
}  // namespace tsubu
