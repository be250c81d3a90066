// The grid of subdomains of a split run (ranks/rank_grid.hpp): the automatic choice, the
// counts of [parallel] fixed along some axes or all, and the counts that fit no grid.
#include <gtest/gtest.h>

#include <array>
#include <stdexcept>

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

}  // namespace
}  // namespace tsubu
