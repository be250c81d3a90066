// The multi-level grid against a brute-force O(N^2) search and the linked-cell grid: the same
// pairs, in the same order, for polydisperse beds, periodic or not, with and without a margin,
// for every number of levels and thread count; its level assignment; and whole runs with
// [search] method = "multilevel" bit-identical to method = "cell".
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/core/random.hpp"
#include "tsubu/core/size_distribution.hpp"
#include "tsubu/integrate/integrators.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/source/build_world.hpp"
#include "scenario_run.hpp"

namespace tsubu {
namespace {

struct Bed {
  Particles p;
  Domain domain;
};

// n grains, number density ∝ d^-2 between d_min and ratio d_min, at random (overlapping)
// positions in a box of 1 x 1.3 x 0.8 proportions holding them at solid fraction phi. Some
// centres are put exactly on the faces (lower, upper, and just below upper) of each axis.
Bed random_bed(std::size_t n, double ratio, std::array<bool, 3> periodic, std::uint64_t seed, double phi = 0.3) {
  Bed b;
  Random rng(seed);
  const double d_min = 1e-3;
  SizeDistribution sizes;
  sizes.kind = ratio > 1 ? SizeDistribution::Kind::talbot : SizeDistribution::Kind::single;
  sizes.diameter = d_min;
  sizes.d_min = d_min, sizes.d_max = ratio * d_min, sizes.exponent = 1;
  std::vector<double> d(n);
  double volume = 0, d_max = 0;
  for (auto& di : d) {
    di = sizes.sample(rng);
    volume += M_PI / 6 * di * di * di;
    d_max = std::max(d_max, di);
  }
  const double shape[3] = {1.0, 1.3, 0.8};
  const double side = std::cbrt(volume / phi / (shape[0] * shape[1] * shape[2]));
  b.domain.periodic = periodic;
  for (int k = 0; k < 3; ++k) {
    b.domain.lower[k] = -0.37 * side;
    b.domain.upper[k] = b.domain.lower[k] + std::max(shape[k] * side, 2.2 * d_max);
  }
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 x;
    for (int k = 0; k < 3; ++k) x[k] = rng.uniform(b.domain.lower[k], b.domain.upper[k]);
    if (i % 50 == 7) {
      const int k = static_cast<int>((i / 50) % 3);
      const int face = static_cast<int>((i / 150) % 3);
      x[k] = face == 0 ? b.domain.lower[k] : face == 1 ? b.domain.upper[k] : std::nextafter(b.domain.upper[k], 0.0 - 1e300);
    }
    b.p.add(static_cast<std::int64_t>(i), 0, d[i], 2500, x, {});
  }
  return b;
}

std::vector<Pair> brute_force(const Particles& p, const Domain& domain, double margin) {
  std::vector<Pair> out;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double reach = p.radius[i] + p.radius[j] + margin;
      if (norm2(domain.separation(p.position[i], p.position[j])) < reach * reach)
        out.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
    }
  return out;
}

bool same(const std::vector<Pair>& a, const std::vector<Pair>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const Pair& x, const Pair& y) {
           return x.i == y.i && x.j == y.j;
         });
}

const double kRatios[] = {1, 2, 5, 10, 20, 50, 100};
const std::array<bool, 3> kPeriodic[] = {{false, false, false}, {true, true, false}, {true, true, true}, {false, true, false}};

TEST(MultiLevelGrid, EqualsBruteForceAndCellGrid) {
  std::uint64_t seed = 1;
  for (double ratio : kRatios)
    for (const auto& periodic : kPeriodic)
      for (double margin : {0.0, 1e-4}) {
        const Bed b = random_bed(1500, ratio, periodic, ++seed);
        const auto expected = brute_force(b.p, b.domain, margin);
        std::vector<Pair> multi, cell;
        MultiLevelGrid ml;
        ml.find_pairs(b.p, b.domain, margin, multi);
        CellGrid cg;
        cg.find_pairs(b.p, b.domain, margin, cell);
        SCOPED_TRACE("ratio " + std::to_string(ratio) + " periodic " + std::to_string(periodic[0]) +
                     std::to_string(periodic[1]) + std::to_string(periodic[2]) + " margin " + std::to_string(margin) +
                     " levels " + std::to_string(ml.levels()));
        EXPECT_GT(expected.size(), 100u);
        EXPECT_TRUE(same(multi, expected)) << multi.size() << " pairs, expected " << expected.size();
        EXPECT_TRUE(same(cell, expected)) << cell.size() << " pairs, expected " << expected.size();
      }
}

TEST(MultiLevelGrid, EveryNumberOfLevelsGivesTheSamePairs) {
  std::uint64_t seed = 100;
  for (double ratio : {5.0, 50.0, 100.0})
    for (const auto& periodic : {kPeriodic[0], kPeriodic[2]}) {
      const Bed b = random_bed(2000, ratio, periodic, ++seed);
      const double margin = 5e-5;
      const auto expected = brute_force(b.p, b.domain, margin);
      MultiLevelGrid ml;
      const int finest = static_cast<int>(ml.estimate(b.p, b.domain, margin).size());
      EXPECT_GE(finest, ratio > 50 ? 7 : 3);
      for (int m = 1; m <= finest + 2; ++m) {
        ml.set_levels(m);
        std::vector<Pair> out;
        ml.find_pairs(b.p, b.domain, margin, out);
        EXPECT_EQ(ml.levels(), m);
        EXPECT_TRUE(same(out, expected)) << "ratio " << ratio << ", " << m << " levels";
      }
    }
}

TEST(MultiLevelGrid, LevelsFollowTheSpecInequality) {
  for (double ratio : kRatios) {
    const Bed b = random_bed(1000, ratio, kPeriodic[1], 7);
    for (int forced : {0, 2, 4, MultiLevelGrid::kMaxLevels}) {
      MultiLevelGrid ml(forced);
      std::vector<Pair> out;
      ml.find_pairs(b.p, b.domain, 0, out);
      const double L = b.domain.length(0), l1 = ml.top_level_size();
      const double d_max = 2 * *std::max_element(b.p.radius.begin(), b.p.radius.end());
      // l_1 = 2^-K0 L with 2^-(K0+1) L < d_max <= 2^-K0 L.
      const double k0 = std::log2(L / l1);
      EXPECT_EQ(k0, std::round(k0));
      EXPECT_LT(l1 / 2, d_max);
      EXPECT_LE(d_max, l1);
      const int m = ml.levels();
      auto size = [&](int k) { return std::ldexp(L, -(k - 1) - static_cast<int>(std::round(k0))); };
      for (std::size_t i = 0; i < b.p.size(); ++i) {
        const double d = 2 * b.p.radius[i];
        const int k = ml.level_of()[i];
        ASSERT_GE(k, 1);
        ASSERT_LE(k, m);
        EXPECT_LE(d, size(k)) << "ratio " << ratio << " particle " << i;
        if (k < m) EXPECT_LT(size(k + 1), d) << "ratio " << ratio << " particle " << i;
      }
    }
  }
}

TEST(MultiLevelGrid, SameForEveryThreadCount) {
  const Bed b = random_bed(12000, 20, kPeriodic[1], 11);
  std::vector<Pair> reference;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    MultiLevelGrid ml;
    std::vector<Pair> out;
    ml.find_pairs(b.p, b.domain, 1e-4, out);
    if (threads == 1) reference = out;
    else EXPECT_TRUE(same(out, reference)) << threads << " threads";
  }
  omp_set_num_threads(1);
  CellGrid cg;
  std::vector<Pair> cell;
  cg.find_pairs(b.p, b.domain, 1e-4, cell);
  EXPECT_TRUE(same(cell, reference));
}

TEST(MultiLevelGrid, FewGrainsInAHugeBoxAndEdgeCases) {
  Bed b;
  b.domain.lower = {0, 0, 0};
  b.domain.upper = {1000, 1000, 1000};
  b.domain.periodic = {true, true, false};
  std::vector<Pair> out;
  MultiLevelGrid ml;
  ml.find_pairs(b.p, b.domain, 0, out);  // no particles
  EXPECT_TRUE(out.empty());
  b.p.add(0, 0, 1e-3, 2500, {0, 0, 5}, {});
  ml.find_pairs(b.p, b.domain, 0, out);
  EXPECT_TRUE(out.empty());
  b.p.add(1, 0, 1e-4, 2500, {999.99996, 0, 5}, {});      // across the x faces: touches 0
  b.p.add(2, 0, 2e-3, 2500, {500, 999.9995, 5.001}, {}); // a lone grain elsewhere
  b.p.add(3, 0, 1e-5, 2500, {500, 0.0005, 5.001}, {});   // across the y faces: touches 2
  b.p.add(4, 0, 1e-5, 2500, {500, 0.0005, 5.001}, {});   // on top of 3
  for (int forced : {0, 1, 3, 8}) {
    ml.set_levels(forced);
    ml.find_pairs(b.p, b.domain, 0, out);
    EXPECT_TRUE(same(out, brute_force(b.p, b.domain, 0))) << forced << " levels";
    EXPECT_TRUE(same(out, {{0, 1}, {2, 3}, {2, 4}, {3, 4}})) << forced << " levels";
  }
}

// Whole runs: the force gather sums touching contacts in (i, j) order, so a correct search
// gives the same bits whatever its method.
World run(const std::string& name, const std::vector<std::string>& overrides) {
  return testing::run_test_scenario(name, overrides);
}

using testing::same_bits;

TEST(MultiLevelGrid, WholeRunBitIdenticalToCellGrid) {
  const World cell = run("poly_search.toml", {"search.method=\"cell\""});
  std::size_t touching = 0;
  for (const auto& c : cell.contacts.pairs()) touching += c.touching;
  EXPECT_GT(touching, 150u) << "the run should have many grain contacts";
  for (const std::string levels : {"", "1", "2", "4"}) {
    std::vector<std::string> set = {"search.method=\"multilevel\""};
    if (!levels.empty()) set.push_back("search.levels=" + levels);
    const World multi = run("poly_search.toml", set);
    SCOPED_TRACE("levels " + (levels.empty() ? std::string("auto") : levels));
    EXPECT_TRUE(same_bits(cell.particles.position, multi.particles.position));
    EXPECT_TRUE(same_bits(cell.particles.velocity, multi.particles.velocity));
    EXPECT_TRUE(same_bits(cell.particles.omega, multi.particles.omega));
    EXPECT_EQ(cell.contacts.pairs().size(), multi.contacts.pairs().size());
  }
}

}  // namespace
}  // namespace tsubu
