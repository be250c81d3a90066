// The contact list (world/contact_list.hpp): a pair is seen from its particle with the
// smaller id, so renumbering the particles mid-run leaves every pair and history as it was,
// bit for bit, and the run continues as the unsorted one does.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cstring>
#include <map>
#include <utility>

#include "tsubu/sim/simulation.hpp"
#include "tsubu/world/spatial_sort.hpp"
#include "scenario_run.hpp"
#include "world_builder.hpp"

namespace tsubu {
namespace {

using IdPair = std::pair<std::int64_t, std::int64_t>;

IdPair ids_of(const Particles& p, const Contact& c) { return std::minmax(p.id[c.i], p.id[c.j]); }

std::map<IdPair, Contact> pairs_by_id(const World& w) {
  std::map<IdPair, Contact> out;
  for (const Contact& c : w.contacts.pairs()) out.emplace(ids_of(w.particles, c), c);
  return out;
}

// A bed being poured (velocity Verlet, friction 0.5), stopped mid-run while grains land on
// it; run once for all tests here.
const std::vector<std::string> kPoured = {"simulation.duration=0.1", "search.sort_every=0"};
const World& poured_bed() {
  static const World bed = testing::run_test_scenario("settle_mono.toml", kPoured);
  return bed;
}

double largest_shift(const World& a, const World& b) {
  std::map<std::int64_t, Vec3> at;
  for (std::size_t i = 0; i < a.particles.size(); ++i) at[a.particles.id[i]] = a.particles.position[i];
  double worst = 0;
  for (std::size_t i = 0; i < b.particles.size(); ++i) worst = std::max(worst, norm(at.at(b.particles.id[i]) - b.particles.position[i]));
  return worst;
}

// Continues a stopped run for `steps` steps (the first kicks with the stored forces, as a
// resume does; the lists are rebuilt from the carried contacts).
World continued(World w, std::int64_t steps) {
  Simulation sim(std::move(w), build_model(testing::test_scenario("settle_mono.toml", kPoured)), Integrator::velocity_verlet, {});
  sim.advance_to(sim.world().step + steps);
  return std::move(sim.world());
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

// Per pair (by ids): the id of its particle with the smaller index (the one the laws saw it
// from when the lists kept pairs in index order).
std::map<IdPair, std::int64_t> index_first_ids(const World& w) {
  std::map<IdPair, std::int64_t> out;
  for (const Contact& c : w.contacts.pairs()) out.emplace(ids_of(w.particles, c), w.particles.id[std::min(c.i, c.j)]);
  return out;
}

TEST(ContactList, RenumberingKeepsEveryHistoryBitForBit) {
  World w = poured_bed();
  const std::map<IdPair, Contact> before = pairs_by_id(w);
  const std::map<IdPair, std::int64_t> first_before = index_first_ids(w);

  sort_spatially(w);

  const Particles& p = w.particles;
  const std::vector<Contact>& pairs = w.contacts.pairs();
  ASSERT_EQ(pairs.size(), before.size());
  std::size_t swapped = 0, springs = 0;
  for (const Contact& c : pairs) {
    const IdPair key = ids_of(p, c);
    const Contact& old = before.at(key);
    EXPECT_EQ(c.touching, old.touching);
    EXPECT_EQ(std::memcmp(&c.history, &old.history, sizeof(ContactHistory)), 0) << "ids " << key.first << ", " << key.second;
    EXPECT_LT(p.id[c.i], p.id[c.j]) << "a pair is seen from its smaller id";
    springs += c.touching && norm2(c.history.xi) > 0;
    // Pairs whose particles' index order the sort reversed keep their orientation.
    swapped += p.id[std::min(c.i, c.j)] != first_before.at(key) && norm2(c.history.xi) > 0;
  }
  EXPECT_GT(springs, 500u) << "the bed should hold many stretched springs";
  EXPECT_GT(swapped, 100u) << "the sort should reverse the index order of many stretched pairs";
  // The list is sorted by (i, id of j) again, and the per-particle index follows it: each
  // particle's pairs in its partners' id order, first those where it is second.
  for (std::size_t k = 1; k < pairs.size(); ++k)
    EXPECT_TRUE(pairs[k - 1].i < pairs[k].i || (pairs[k - 1].i == pairs[k].i && p.id[pairs[k - 1].j] < p.id[pairs[k].j]));
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::int64_t last = INT64_MIN;
    w.contacts.for_each_pair_of(i, [&](std::uint32_t j, std::uint32_t k) {
      const Contact& c = pairs[k];
      EXPECT_TRUE((c.i == i && c.j == j) || (c.j == i && c.i == j));
      EXPECT_LT(last, p.id[j]);
      last = p.id[j];
    });
    w.contacts.for_each_contact_of(i, [&](std::uint32_t k, auto side) {
      if constexpr (decltype(side)::value < 0) EXPECT_EQ(pairs[k].j, i);
      else if constexpr (decltype(side)::value > 0) EXPECT_EQ(pairs[k].i, i);
      else EXPECT_EQ(w.contacts.walls()[k].i, i);
    });
  }
}

// Sorting mid-run changes nothing: each particle sums its forces in its partners' id order
// and a pair's forces do not depend on which of its particles comes first, so 300 more steps
// after a sort end with the bits of the unsorted continuation (when the sums followed the
// indices they differed by 2e-16 m). Reversing the stored springs of the pairs whose smaller
// index changed, as the sort did when histories were kept by index, moves a grain by 1.6 cm.
TEST(ContactList, ARunSortedMidwayContinuesTheUnsortedRun) {
  const World& bed = poured_bed();
  const std::map<IdPair, std::int64_t> first_before = index_first_ids(bed);
  World sorted = bed;
  sort_spatially(sorted);
  World flipped = sorted;
  for (Contact& c : flipped.contacts.pairs())
    if (flipped.particles.id[std::min(c.i, c.j)] != first_before.at(ids_of(flipped.particles, c))) c.history.xi = -c.history.xi;

  const World plain_end = continued(bed, 300);
  const double shift = largest_shift(plain_end, continued(std::move(sorted), 300));
  EXPECT_EQ(shift, 0.0);
  ::testing::Test::RecordProperty("largest_position_difference_m", ::testing::PrintToString(shift));
  const double wrong = largest_shift(plain_end, continued(std::move(flipped), 300));
  EXPECT_GT(wrong, 1e-3 * 0.002) << "springs reversed by the sort should show";
  ::testing::Test::RecordProperty("largest_difference_with_reversed_springs_m", ::testing::PrintToString(wrong));
}

// Two grains pressed together, the second sliding and rolling over the first (friction
// 0.5), with ids in or against the index order.
testing::Bed sliding_pair(std::int64_t first_id, std::int64_t second_id, double dt) {
  testing::Bed bed = testing::make_world({"grain", 2500, 1e7, 0.3}, testing::spec_of("hertz_tsuji", "mindlin", 0.5, 0.5), dt);
  World& w = bed.world;
  w.particles.add(first_id, 0, 0.01, 2500, {0, 0, 0}, {});
  w.particles.add(second_id, 0, 0.01, 2500, {0.009999, 0, 0}, {-0.05, 0.05, 0.02});
  w.particles.omega[1] = {3, -1, 2};
  return bed;
}

// Ids against the index order change the particle the laws see the pair from (its smaller
// id), not what they compute: the pair moves by the same bits either way, with fixed steps
// and with block steps (the rates evaluation), and its stored spring is the other one's
// negated.
TEST(ContactList, IdsAgainstTheIndexOrderGiveTheSameBits) {
  for (const Integrator integrator : {Integrator::velocity_verlet, Integrator::block_hermite}) {
    const double dt = integrator == Integrator::block_hermite ? 1e-4 : 1e-6;
    const std::int64_t steps = integrator == Integrator::block_hermite ? 10 : 1000;
    std::vector<World> end;
    for (const auto& [a, b] : {std::pair{0, 1}, std::pair{1, 0}}) {
      testing::Bed pair = sliding_pair(a, b, dt);
      Simulation sim(std::move(pair.world), std::move(pair.model), integrator, {});
      sim.start();
      sim.advance_to(steps);
      end.push_back(std::move(sim.world()));
    }
    const Contact& in_order = end[0].contacts.pairs().at(0);
    const Contact& against = end[1].contacts.pairs().at(0);
    ASSERT_TRUE(in_order.touching) << "the grains must still touch";
    EXPECT_GT(norm(in_order.history.xi), 1e-7) << "the spring must be stretched";
    EXPECT_TRUE(same_bits(against.history.xi, -in_order.history.xi));
    EXPECT_TRUE(testing::same_bits(end[0].particles.position, end[1].particles.position));
    EXPECT_TRUE(testing::same_bits(end[0].particles.velocity, end[1].particles.velocity));
    EXPECT_TRUE(testing::same_bits(end[0].particles.omega, end[1].particles.omega));
  }
}

}  // namespace
}  // namespace tsubu
