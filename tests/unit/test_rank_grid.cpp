// The grid of subdomains of a split run (ranks/rank_grid.hpp): the automatic choice, the
// counts of [parallel] fixed along some axes or all, the counts that fit no grid, and the
// cuts that follow the work.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "tsubu/ranks/rank_grid.hpp"

namespace tsubu {
namespace {

// A tall box (a sedimentation column): 1 x 1 x 4.
const Domain kColumn{{0, 0, 0}, {1, 1, 4}, {true, true, false}};

TEST(RankGrid, AutomaticCountsHaveTheLeastSurface) {
  EXPECT_EQ(RankGrid(kColumn, 4).counts(), (std::array<int, 3>{1, 1, 4}));  // cubes of 1
  EXPECT_EQ(RankGrid(kColumn, 2).counts(), (std::array<int, 3>{1, 1, 2}));
  EXPECT_EQ(RankGrid(kColumn, 1).counts(), (std::array<int, 3>{1, 1, 1}));
}

TEST(RankGrid, GivenCountsFixTheirAxesAndTheOthersAreChosen) {
  // Columns for a deposit: no cut along z; x and y chosen (ties: the fewest cuts along x).
  EXPECT_EQ(RankGrid(kColumn, 4, {0, 0, 1}).counts(), (std::array<int, 3>{2, 2, 1}));
  EXPECT_EQ(RankGrid(kColumn, 2, {0, 0, 1}).counts(), (std::array<int, 3>{1, 2, 1}));
  EXPECT_EQ(RankGrid(kColumn, 6, {0, 3, 0}).counts(), (std::array<int, 3>{1, 3, 2}));
  EXPECT_EQ(RankGrid(kColumn, 6, {3, 2, 1}).counts(), (std::array<int, 3>{3, 2, 1}));
  // Every process owns one subdomain: the owners of the subdomains' centres are 0..N-1.
  const RankGrid g(kColumn, 4, {0, 0, 1});
  EXPECT_EQ(g.owner({0.25, 0.25, 2}), 0);
  EXPECT_EQ(g.owner({0.75, 0.25, 2}), 1);
  EXPECT_EQ(g.owner({0.25, 0.75, 2}), 2);
  EXPECT_EQ(g.owner({0.75, 0.75, 2}), 3);
}

TEST(RankGrid, CountsThatFitNoGridAreRefused) {
  EXPECT_TRUE(RankGrid::fits({0, 0, 0}, 7));
  EXPECT_TRUE(RankGrid::fits({7, 0, 0}, 7));
  EXPECT_FALSE(RankGrid::fits({2, 0, 0}, 3));  // 2 does not divide 3
  EXPECT_FALSE(RankGrid::fits({2, 2, 1}, 3));
  EXPECT_FALSE(RankGrid::fits({1, 1, 1}, 2));
  EXPECT_FALSE(RankGrid::fits({2, 3, 0}, 4));
  EXPECT_THROW(RankGrid(kColumn, 3, {2, 0, 0}), std::invalid_argument);
}

// The work of a deposit: all of it in the lowest quarter of the column, evenly. Four slabs
// along z share it: their cuts move down into the quarter, a sixteenth of the column apart,
// and the owners follow them; the axes that are not cut, or that hold no work, keep theirs.
TEST(RankGrid, TheCutsFollowTheWork) {
  RankGrid g(kColumn, 4, {1, 1, 4});
  EXPECT_EQ(g.cuts(2), (std::vector<double>{0, 1, 2, 3, 4}));
  std::array<std::vector<std::int64_t>, 3> work;
  for (int a = 0; a < 3; ++a) work[static_cast<std::size_t>(a)].assign(static_cast<std::size_t>(g.bins(a)), 0);
  EXPECT_EQ(g.bins(2), 4 * RankGrid::kBinsPerSlab);
  for (int b = 0; b < RankGrid::kBinsPerSlab; ++b) work[2][static_cast<std::size_t>(b)] = 3;  // z below 1
  work[0][0] = 7;  // x is not cut
  g.balance(work);
  EXPECT_EQ(g.cuts(2), (std::vector<double>{0, 0.25, 0.5, 0.75, 4}));
  EXPECT_EQ(g.cuts(0), (std::vector<double>{0, 1}));
  EXPECT_EQ(g.owner({0.5, 0.5, 0.1}), 0);
  EXPECT_EQ(g.owner({0.5, 0.5, 0.3}), 1);
  EXPECT_EQ(g.owner({0.5, 0.5, 0.5}), 2);  // a position on a cut: the slab above
  EXPECT_EQ(g.owner({0.5, 0.5, 3.9}), 3);
  std::vector<int> near;
  g.near({0.5, 0.5, 0.5}, 0.3, 2, near);  // within 0.3 of the slabs [0.25, 0.5) and [0.75, 4]
  EXPECT_EQ(near, (std::vector<int>{0, 1, 3}));

  // All the work in one bin: each slab keeps at least one bin, the last slab the rest.
  for (auto& w : work[2]) w = 0;
  work[2][10] = 5;
  g.balance(work);
  const double bin = 4.0 / g.bins(2);
  EXPECT_DOUBLE_EQ(g.cuts(2)[1], 11 * bin);
  EXPECT_DOUBLE_EQ(g.cuts(2)[2], 12 * bin);
  EXPECT_DOUBLE_EQ(g.cuts(2)[3], 13 * bin);
  for (auto& w : work[2]) w = 0;  // no work: the cuts stay
  g.balance(work);
  EXPECT_DOUBLE_EQ(g.cuts(2)[3], 13 * bin);
}

}  // namespace
}  // namespace tsubu
