// Deposit measurements (analysis/deposit.hpp) against analytic cases: lattices of known solid
// fraction, a sphere cut by a slab, Monte Carlo against exact volumes, hand-made contact counts.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tsubu/analysis/deposit.hpp"
#include "tsubu/source/sources.hpp"

namespace tsubu {
namespace {

struct Grains {
  Domain domain;
  std::vector<Vec3> position;
  std::vector<double> radius;
  Packing packing() const { return {domain, position, radius}; }
};

// A periodic box of n x n cubic cells of side c in x-y, `layers` cells high from z = 0, with
// one grain of diameter d at each of the cell's `basis` points.
Grains lattice(int n, int layers, double c, double d, const std::vector<Vec3>& basis) {
  Grains g;
  g.domain = {{0, 0, 0}, {n * c, n * c, 10 * n * c}, {true, true, false}};
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const Vec3& b : basis) {
          g.position.push_back((Vec3{double(i), double(j), double(k)} + b) * c);
          g.radius.push_back(0.5 * d);
        }
  return g;
}

Grains simple_cubic(int n, int layers, double d) { return lattice(n, layers, d, d, {{0.5, 0.5, 0.5}}); }

Grains face_centred_cubic(int n, int layers, double d) {
  return lattice(n, layers, d * std::sqrt(2.0), d, {{0.25, 0.25, 0.25}, {0.75, 0.75, 0.25}, {0.75, 0.25, 0.75}, {0.25, 0.75, 0.75}});
}

TEST(Deposit, LatticeSolidFractionExactAndMonteCarlo) {
  const double d = 0.01;
  struct Case {
    Grains g;
    double phi, period;
  } cases[] = {{simple_cubic(6, 8, d), M_PI / 6, d}, {face_centred_cubic(4, 6, d), M_PI / (3 * std::sqrt(2.0)), d * std::sqrt(2.0)}};
  for (const Case& c : cases) {
    // Any slab of a whole number of periods holds the lattice's solid fraction.
    const double a = 1.3 * c.period, b = a + 3 * c.period;
    EXPECT_NEAR(solid_fraction(c.g.packing(), a, b), c.phi, 1e-12);
    const PorosityEstimate e = porosity_monte_carlo(c.g.packing(), a, b, 65536, 7);
    EXPECT_LT(e.standard_error, 0.002);
    EXPECT_NEAR(e.porosity, 1 - c.phi, 3 * e.standard_error);
    EXPECT_EQ(e.points, 65536);
  }
}

TEST(Deposit, SphereCutBySlabIsTwoCaps) {
  // A sphere of radius r at z = 0 in the slab -h1 < z < h2 (both inside it): the sphere minus
  // the caps of heights r - h1 and r - h2, a cap of height h being pi h^2 (3r - h)/3.
  const double r = 1, h1 = 0.3, h2 = 0.6;
  Grains g;
  g.domain = {{-2, -2, -5}, {2, 2, 5}, {true, true, false}};
  g.position = {{1.9, -1.8, 0}};  // close to a corner: the periodic sides wrap it
  g.radius = {r};
  auto cap = [r](double h) { return M_PI * h * h * (3 * r - h) / 3; };
  const double expected = 4.0 / 3.0 * M_PI - cap(r - h1) - cap(r - h2);
  EXPECT_NEAR(solid_volume(g.packing(), -h1, h2), expected, 1e-12);
  const PorosityEstimate e = porosity_monte_carlo(g.packing(), -h1, h2, 100000, 3);
  EXPECT_NEAR(e.porosity, 1 - expected / (16 * (h1 + h2)), 3 * e.standard_error);
}

TEST(Deposit, MonteCarloAgreesWithExactOnARandomPacking) {
  ParticleSource src;
  src.lower = {0, 0, 0};
  src.upper = {0.04, 0.04, 0.06};
  src.solid_fraction = 0.35;
  src.sizes.kind = SizeDistribution::Kind::talbot;
  src.sizes.d_min = 0.002;
  src.sizes.d_max = 0.01;
  Domain domain{src.lower, src.upper, {true, true, false}};
  Random rng(11);
  Grains g;
  g.domain = domain;
  for (const Grain& grain : random_grains(src, domain, rng)) {
    g.position.push_back(grain.position);
    g.radius.push_back(0.5 * grain.diameter);
  }
  const double a = 0.015, b = 0.035;
  const double exact = 1 - solid_fraction(g.packing(), a, b);
  const PorosityEstimate e = porosity_monte_carlo(g.packing(), a, b, 65536, 2);
  EXPECT_NEAR(e.porosity, exact, 3 * e.standard_error);
  // The same seed gives the same points.
  EXPECT_EQ(e.porosity, porosity_monte_carlo(g.packing(), a, b, 65536, 2).porosity);
}

TEST(Deposit, HeightBySlices) {
  // A simple cubic deposit (solid fraction pi/6 = 0.52) of 6 layers of 0.05 fills 0 < z < 0.3:
  // below 0.1, 0.2, 0.3 the solid fraction is 0.52, below 0.4 it is 0.39.
  const Grains g = simple_cubic(20, 6, 0.05);
  SliceRule rule{0, 0.1, 10, 0.5};
  EXPECT_NEAR(deposit_height(g.packing(), rule), 0.3, 1e-12);
  rule.threshold = 0.6;  // the paper's threshold: never reached by a simple cubic packing
  EXPECT_EQ(deposit_height(g.packing(), rule), 0.0);
}

TEST(Deposit, SurfaceIsTheTopOfAUniformDepositWhateverItsDensity) {
  // Simple cubic deposits of `layers` layers at spacing s fill 0 < z < layers s with solid
  // fraction (pi/6) (d/s)^3: 0.52 touching, 0.45 at s = 1.05 d. A window of one spacing holds
  // exactly the lattice's solid fraction inside the deposit and half of it when centred on
  // the top: the surface is layers s for both densities.
  const double d = 0.01;
  for (double s : {d, 1.05 * d})
    for (int layers : {1, 3, 6}) {
      Grains g = lattice(8, layers, s, d, {{0.5, 0.5, 0.5}});
      const SurfaceRule rule{0, s, g.domain.upper.z};
      EXPECT_NEAR(surface_height(g.packing(), rule), layers * s, 1e-9 * d) << "s = " << s << ", layers = " << layers;
    }
}

TEST(Deposit, SurfaceRisesWithTheFirstGrainAndIgnoresGrainsAbove) {
  Grains g;
  g.domain = {{0, 0, 0}, {0.04, 0.04, 0.1}, {true, true, false}};
  const SurfaceRule rule{0, 0.01, 0.1};
  EXPECT_EQ(surface_height(g.packing(), rule), 0.0);  // no grain
  g.position = {{0.02, 0.02, 0.05}};                  // a grain falling far above the floor
  g.radius = {0.005};
  EXPECT_EQ(surface_height(g.packing(), rule), 0.0);
  g.position.push_back({0.01, 0.01, 0.005});  // the first grain on the floor
  g.radius.push_back(0.005);
  const double first = surface_height(g.packing(), rule);
  EXPECT_GT(first, 0.0);
  EXPECT_LE(first, 0.005);  // a sparse first layer: below the window's centre; the falling grain is not counted
  // Layer by layer (a simple cubic deposit growing by one layer at a time), the surface
  // never falls and ends at the deposit's top.
  double last = 0;
  for (int layers = 1; layers <= 5; ++layers) {
    Grains lat = simple_cubic(4, layers, 0.01);
    const double h = surface_height(lat.packing(), SurfaceRule{0, 0.01, lat.domain.upper.z});
    EXPECT_GT(h, last);
    last = h;
  }
  EXPECT_NEAR(last, 0.05, 1e-12);
}

TEST(Deposit, CoordinationWithBothRattlerDefinitions) {
  const std::vector<Vec3> x = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 5}};
  const std::vector<int> z = {0, 1, 2, 3, 4, 6, 10};  // the last grain is outside the slab
  const Coordination c = coordination_numbers(x, z, 0, 2);
  EXPECT_EQ(c.grains, 6);
  EXPECT_EQ(c.rattlers_2, 2);
  EXPECT_EQ(c.rattlers_4, 4);
  EXPECT_DOUBLE_EQ(c.all, 16.0 / 6);
  EXPECT_DOUBLE_EQ(c.without_rattlers_2, 15.0 / 4);
  EXPECT_DOUBLE_EQ(c.without_rattlers_4, 10.0 / 2);
  EXPECT_EQ(grains_in_slab(x, 0, 2), 6);
}

TEST(Deposit, SmallGrainShareOfLayers) {
  // Lower layer: one large grain (d = 0.3) and two small (d = 0.1); upper: one small only.
  Grains g;
  g.domain = {{0, 0, 0}, {1, 1, 2}, {true, true, false}};
  g.position = {{0.5, 0.5, 0.5}, {0.1, 0.1, 0.5}, {0.8, 0.8, 0.5}, {0.5, 0.5, 1.5}};
  g.radius = {0.15, 0.05, 0.05, 0.05};
  EXPECT_NEAR(small_grain_share(g.packing(), 0, 1, 0.11), 2 * 0.001 / (2 * 0.001 + 0.027), 1e-12);  // d^3 ratios
  EXPECT_NEAR(small_grain_share(g.packing(), 1, 2, 0.1), 0, 1e-15);  // d = 0.1 is not below a threshold of 0.1
  EXPECT_NEAR(small_grain_share(g.packing(), 1, 2, 0.11), 1, 1e-15);
  EXPECT_EQ(small_grain_share(g.packing(), 3, 4, 0.1), 0);  // no solid
}

}  // namespace
}  // namespace tsubu
