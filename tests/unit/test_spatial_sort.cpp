// Spatial sorting (world/spatial_sort.hpp): particles move with everything they carry, contact
// histories follow their pairs, and a run sorted every few steps is the same physics.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/world/spatial_sort.hpp"
#include "final_state.hpp"
#include "scenario_run.hpp"
#include "tsubu_process.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

// Four grains placed against the Morton order, two pair contacts (one whose particles swap
// index order) and a wall contact, each with its own history (stored from the smaller id:
// here ids and indices have the same order).
TEST(SpatialSort, ParticlesCarryTheirDataAndContactsFollow) {
  auto [w, model] = testing::make_world({"grain", 2500, 1e7, 0.3}, testing::spec_of("hertz_tsuji", "mindlin", 0.5, 0.5), 1e-6);
  w.domain = {{0, 0, 0}, {1, 1, 1}, {false, false, false}};
  const Vec3 at[4] = {{0.9, 0.9, 0.9}, {0.1, 0.1, 0.1}, {0.9, 0.1, 0.1}, {0.1, 0.9, 0.1}};
  for (int k = 0; k < 4; ++k) w.particles.add(10 + k, 0, 0.01 * (k + 1), 2500, at[k], {double(k), 0, 0});
  for (int k = 0; k < 4; ++k) w.particles.force[k] = {0, 0, double(k)};
  w.contacts.assign({{0, 1, true, {{1, 2, 3}, {4, 0}}}, {1, 2, true, {{5, 6, 7}, {8, 0}}}},
                    {{0, 0, true, {{9, 9, 9}, {0, 0}}}}, w.particles);
  const Vec3* positions = w.particles.position.data();
  const std::int64_t* ids = w.particles.id.data();
  sort_spatially(w);
  // In place: views into the arrays (the Python binding's NumPy arrays) stay valid.
  EXPECT_EQ(w.particles.position.data(), positions);
  EXPECT_EQ(w.particles.id.data(), ids);

  const Particles& p = w.particles;
  // Morton order of the cells: (0.1,0.1,0.1) < (0.9,0.1,0.1) < (0.1,0.9,0.1) < (0.9,0.9,0.9).
  EXPECT_EQ(p.id, (std::vector<std::int64_t>{11, 12, 13, 10}));
  for (std::size_t i = 0; i < 4; ++i) {
    const int k = static_cast<int>(p.id[i] - 10);
    EXPECT_EQ(p.position[i], at[k]);
    EXPECT_EQ(p.velocity[i].x, k);
    EXPECT_EQ(p.force[i].z, k);
    EXPECT_DOUBLE_EQ(p.radius[i], 0.005 * (k + 1));
  }
  // Pair ids (11, 12) became indices (0, 1). Ids (10, 11) became (3, 0): still seen from
  // id 10, now the larger index, with its history unchanged. Sorted by (i, id of j).
  const std::vector<Contact>& pairs = w.contacts.pairs();
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].i, 0u);
  EXPECT_EQ(pairs[0].j, 1u);
  EXPECT_EQ(pairs[0].history.xi, (Vec3{5, 6, 7}));
  EXPECT_EQ(pairs[0].history.normal[0], 8);
  EXPECT_EQ(pairs[1].i, 3u);
  EXPECT_EQ(pairs[1].j, 0u);
  EXPECT_EQ(pairs[1].history.xi, (Vec3{1, 2, 3})) << "seen from id 10, whatever the indices";
  EXPECT_EQ(pairs[1].history.normal[0], 4);
  ASSERT_EQ(w.contacts.walls().size(), 1u);
  EXPECT_EQ(w.contacts.walls()[0].i, 3u);
  EXPECT_EQ(w.contacts.walls()[0].history.xi, (Vec3{9, 9, 9}));
}

// The largest distance between a grain's positions in two runs of the same grains (by id).
double largest_move(const World& a, const World& b) {
  EXPECT_EQ(a.particles.size(), b.particles.size());
  if (a.particles.size() != b.particles.size()) return INFINITY;
  std::vector<std::size_t> index_of(a.particles.size());
  for (std::size_t i = 0; i < b.particles.size(); ++i) index_of[static_cast<std::size_t>(b.particles.id[i])] = i;
  double worst = 0;
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    const std::size_t k = index_of[static_cast<std::size_t>(a.particles.id[i])];
    worst = std::max(worst, norm(a.particles.position[i] - b.particles.position[k]));
  }
  return worst;
}

// Whether two runs of the same grains end with the same bits: positions, velocities and
// spins, grain by grain (by id).
bool same_bits_by_id(const World& a, const World& b) {
  if (a.particles.size() != b.particles.size()) return false;
  std::vector<std::size_t> index_of(a.particles.size());
  for (std::size_t i = 0; i < b.particles.size(); ++i) index_of[static_cast<std::size_t>(b.particles.id[i])] = i;
  const auto same = [](const Vec3& u, const Vec3& v) { return std::memcmp(&u, &v, sizeof(Vec3)) == 0; };
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    const std::size_t k = index_of[static_cast<std::size_t>(a.particles.id[i])];
    if (!same(a.particles.position[i], b.particles.position[k]) || !same(a.particles.velocity[i], b.particles.velocity[k]) ||
        !same(a.particles.omega[i], b.particles.omega[k]))
      return false;
  }
  return true;
}

World run(const std::vector<std::string>& overrides) { return testing::run_test_scenario("settle_mono.toml", overrides); }

// Each particle sums its contact forces in the order of its partners' ids, so a bed being
// poured, sorted every 500 steps, ends with the same bits as the unsorted run after 3000
// steps. When the sums followed the indices it stayed within round-off (1e-15 m); forgetting
// to orient the spring of a pair whose particles swap order by its ids moves grains by 2e-5 m.
TEST(SpatialSort, SortedRunIsTheSameBits) {
  const World plain = run({"simulation.duration=0.03", "search.sort_every=0"});
  const World sorted = run({"simulation.duration=0.03", "search.sort_every=500"});
  ASSERT_NE(plain.particles.id, sorted.particles.id) << "the sort should have reordered the lattice";
  EXPECT_TRUE(same_bits_by_id(plain, sorted)) << "largest position difference " << largest_move(plain, sorted) << " m";
}

// Block steps: the Simulation's one renumbering moves the Hermite state (times, levels,
// accelerations and their derivatives) with the particles. Sorted every third step, ~300
// grains settling in water end with the bits of the unsorted run after 250 steps (when the
// sums followed the indices, within 1.6e-12 m: the release mark divides a gap of a few
// nanometres, whose last bits the order of the sums set, by its rate of opening); a
// renumbering that left the Hermite state behind moves them by millimetres or stops the run.
TEST(SpatialSort, SortedBlockStepRunIsTheSameBits) {
  const std::vector<std::string> common = {"simulation.duration=0.025"};
  auto with = [&](const char* sort) {
    std::vector<std::string> o = common;
    o.push_back(sort);
    return testing::run_test_scenario("block_sediment.toml", o);
  };
  const World plain = with("search.sort_every=0");
  const World sorted = with("search.sort_every=3");
  ASSERT_NE(plain.particles.id, sorted.particles.id) << "the sort should have reordered the grains";
  EXPECT_TRUE(same_bits_by_id(plain, sorted)) << "largest position difference " << largest_move(plain, sorted) << " m";
}

// The files a run writes do not depend on how the engine numbers its particles: sorted in
// space every few steps or never, a run writes the same series, particle frames and contact
// networks byte for byte (frames list the particles by id, contacts by their ids, each pair
// seen from its smaller id), and the same final checkpoint but for timings, the rebuild
// count and the --set that differs (particles by id, touching contacts only, the energy
// watch's sums exact; block steps credit a cluster's step to its member with the smallest
// id): fixed steps on a floor with periodic sides, block steps with the inflow, and
// hindered settling (each grain sums its neighbours' volumes in their ids' order).
TEST(SpatialSort, SortedRunWritesTheSameFiles) {
  namespace fs = std::filesystem;
  const testing::TempDir tmp;
  const std::string src = TSUBU_SOURCE_DIR;
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"/tests/scenarios/settle_mono.toml", {"simulation.duration=0.02", "output.vtk_interval=0.005"}},
      {"/tests/scenarios/rain_small.toml", {"simulation.duration=0.08"}},
      {"/tests/scenarios/inflow_small.toml", {"fluid.hindered_settling=true", "output.vtk_interval=0.1"}}};
  for (const auto& [scenario, sets] : cases) {
    std::vector<fs::path> out;
    for (const char* sort : {"search.sort_every=0", "search.sort_every=3"}) {
      out.push_back(tmp.path() / (fs::path(scenario).stem().string() + "_" + sort));
      std::vector<std::string> args = {"run", src + scenario, "--out", out.back().string(), "--set", sort};
      for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
      ASSERT_EQ(testing::run(args, out.back().string() + ".log"), 0) << testing::slurp(out.back().string() + ".log");
    }
    int compared = 0;
    for (const auto& entry : fs::recursive_directory_iterator(out[0] / "frames")) {
      if (!entry.is_regular_file()) continue;
      const fs::path other = out[1] / fs::relative(entry.path(), out[0]);
      EXPECT_EQ(testing::slurp(entry.path()), testing::slurp(other)) << other;
      ++compared;
    }
    EXPECT_EQ(testing::slurp(out[0] / "series.csv"), testing::slurp(out[1] / "series.csv")) << scenario;
    EXPECT_TRUE(testing::final_state(out[0], true) == testing::final_state(out[1], true)) << scenario << ": final checkpoints differ";
    EXPECT_GE(compared, 4) << scenario << ": frames with particles and contacts expected";
  }
}

}  // namespace
}  // namespace tsubu
