// Contact search against brute force; particle sources and packing measures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/core/size_distribution.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/source/sources.hpp"

namespace tsubu {
namespace {

std::vector<Pair> brute_force(const Particles& p, const Domain& d, double margin) {
  std::vector<Pair> out;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t j = i + 1; j < p.size(); ++j) {
      const double reach = p.radius[i] + p.radius[j] + margin;
      if (norm2(d.separation(p.position[i], p.position[j])) < reach * reach) out.push_back({i, j});
    }
  return out;
}

class CellGridVsBruteForce : public ::testing::TestWithParam<std::tuple<double, bool>> {};

TEST_P(CellGridVsBruteForce, SamePairsInTheSameOrder) {
  const auto [size_ratio, periodic] = GetParam();
  Domain d{{0, 0, 0}, {1, 0.8, 0.6}, {periodic, periodic, false}};
  Random rng(42);
  Particles p;
  const double d_max = 0.1;
  for (int k = 0; k < 1500; ++k) {
    const double diameter = d_max * std::pow(1 / size_ratio, rng.uniform());  // log-uniform
    p.add(k, 0, diameter, 1, {rng.uniform(0, 1), rng.uniform(0, 0.8), rng.uniform(0, 0.6)}, {});
  }
  CellGrid grid;
  for (double margin : {0.0, 0.01}) {
    std::vector<Pair> found;
    grid.find_pairs(p, d, margin, found);
    const std::vector<Pair> expected = brute_force(p, d, margin);
    ASSERT_EQ(found.size(), expected.size()) << "size ratio " << size_ratio << ", margin " << margin;
    for (std::size_t k = 0; k < found.size(); ++k) {
      EXPECT_EQ(found[k].i, expected[k].i);
      EXPECT_EQ(found[k].j, expected[k].j);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SizeRatios, CellGridVsBruteForce,
                         ::testing::Combine(::testing::Values(1.0, 3.0, 10.0), ::testing::Bool()));

TEST(SizeDistribution, TalbotSamplesFollowTheNumberDensity) {
  // n(d) ∝ d^{S-3} on [d_min, d_max]: the fraction below the geometric midpoint d_g is
  // (d_g^{S-2} - d_min^{S-2}) / (d_max^{S-2} - d_min^{S-2}); for S = 2 it is 1/2.
  for (double S : {0.0, 1.0, 2.0}) {
    SizeDistribution dist;
    dist.kind = SizeDistribution::Kind::talbot;
    dist.d_min = 1e-3;
    dist.d_max = 1e-2;
    dist.exponent = S;
    Random rng(1);
    const double dg = std::sqrt(dist.d_min * dist.d_max);
    const int n = 200000;
    int below = 0;
    for (int k = 0; k < n; ++k) {
      const double d = dist.sample(rng);
      ASSERT_GE(d, dist.d_min);
      ASSERT_LE(d, dist.d_max);
      below += d < dg;
    }
    const double k = S - 2;
    const double expected = S == 2 ? 0.5 : (std::pow(dg, k) - std::pow(dist.d_min, k)) / (std::pow(dist.d_max, k) - std::pow(dist.d_min, k));
    const double sigma = std::sqrt(expected * (1 - expected) / n);  // binomial standard error
    EXPECT_NEAR(static_cast<double>(below) / n, expected, 5 * sigma) << "S = " << S;
  }
}

TEST(SizeDistribution, LognormalMedianAndBounds) {
  SizeDistribution dist;
  dist.kind = SizeDistribution::Kind::lognormal;
  dist.median = 2e-3;
  dist.sigma = 0.3;
  dist.d_min = 1e-3;
  dist.d_max = 4e-3;
  Random rng(5);
  std::vector<double> d(100001);
  for (double& x : d) x = dist.sample(rng);
  std::nth_element(d.begin(), d.begin() + 50000, d.end());
  EXPECT_NEAR(d[50000], 2e-3, 2e-3 * 0.01);  // the truncation is symmetric in ln d
  EXPECT_GE(*std::min_element(d.begin(), d.end()), 1e-3);
  EXPECT_LE(*std::max_element(d.begin(), d.end()), 4e-3);
}

TEST(Measures, SphereSlabVolume) {
  const double r = 1.0, full = 4.0 / 3.0 * M_PI;
  EXPECT_NEAR(sphere_slab_volume(0, r, -2, 2), full, 1e-14);
  EXPECT_NEAR(sphere_slab_volume(0, r, 0, 5), full / 2, 1e-14);
  EXPECT_NEAR(sphere_slab_volume(0, r, 0.5, 1), M_PI * 0.5 * 0.5 * (3 - 0.5) / 3, 1e-14);  // cap of height h: pi h^2 (3r - h)/3
  EXPECT_EQ(sphere_slab_volume(0, r, 1.5, 2), 0.0);
}

TEST(CsvSource, HeaderMayFollowCommentsAndVelocitiesAreOptional) {
  const std::string path = ::testing::TempDir() + "tsubu_csv_header.csv";
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fputs("# settled bed\n\nx,y,z,d,vx,vy,vz\n0.1,0.2,0.3,0.002,1,2,3\n0.5,0.5,0.5,0.004\r\n", f);
  std::fclose(f);
  ParticleSource src;
  src.file = path;
  const std::vector<Grain> g = read_csv_grains(src);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].position, (Vec3{0.1, 0.2, 0.3}));
  EXPECT_EQ(g[0].velocity, (Vec3{1, 2, 3}));
  EXPECT_EQ(g[0].where.line, 4);
  EXPECT_EQ(g[1].diameter, 0.004);
  EXPECT_EQ(g[1].velocity, (Vec3{}));
}

// The particle state tsubu export writes: every column read back, materials and spins per row.
TEST(FileSource, ReadsTheExportedStateRowByRow) {
  std::istringstream in(
      "id,material,radius[m],x[m],y[m],z[m],vx[m/s],vy[m/s],vz[m/s],wx[rad/s],wy[rad/s],wz[rad/s]\n"
      "0,1,0.0005,0.1,0.2,0.3,1,2,3,4,5,6\n"
      "1,0,0.00075,0.4,0.5,0.6,0,0,-1,0,0,7\n");
  const std::vector<Grain> g = parse_state_grains(in, "bed.csv", 2);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].material, 1);
  EXPECT_EQ(g[0].diameter, 0.001);
  EXPECT_EQ(g[0].position, (Vec3{0.1, 0.2, 0.3}));
  EXPECT_EQ(g[0].velocity, (Vec3{1, 2, 3}));
  EXPECT_EQ(g[0].omega, (Vec3{4, 5, 6}));
  EXPECT_EQ(g[1].where.line, 3);
  EXPECT_EQ(g[1].material, 0);
}

// Bad rows: file:line: column: what is wrong and what is allowed.
TEST(FileSource, BadRowsNameTheLineAndTheColumn) {
  auto message = [](const std::string& rows) {
    std::istringstream in("id,material,radius[m],x[m],y[m],z[m],vx[m/s],vy[m/s],vz[m/s],wx[rad/s],wy[rad/s],wz[rad/s]\n" + rows);
    try {
      parse_state_grains(in, "bed.csv", 2);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("0,2,0.0005,0,0,0,0,0,0,0,0,0\n"),
            "bed.csv:2: material: must be the index of one of the scenario's 2 [[materials]] (0 to 1, in the order of the file)");
  EXPECT_EQ(message("0,0,0.0005,0,0,0,0,0,0\n"),
            "bed.csv:2: expected 12 numbers, got 9; rows are id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz in SI units, as "
            "tsubu export writes them");
  EXPECT_EQ(message("0,0,0.0005,0,0,0,0,0,0,0,0,0\n1.5,0,0.0005,0,0,0,0,0,0,0,0,0\n"), "bed.csv:3: id: must be an integer");
  EXPECT_EQ(message("0,0,0,0,0,0,0,0,0,0,0,0\n"), "bed.csv:2: radius: the radius must be > 0 (metres)");
  EXPECT_NE(message("0,0,0.0005,0,abc,0,0,0,0,0,0,0\n").find("bed.csv:2: y: \"abc\" is not a finite number"), std::string::npos);
  EXPECT_EQ(message(""), "bed.csv:1: no particles in the file");
}

}  // namespace
}  // namespace tsubu
