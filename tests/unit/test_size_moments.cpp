// The samplers of size_distribution.hpp against the closed-form moments of size_moments.hpp,
// Talbot by (S, Sigma, d_max) including S = 2 (n ∝ 1/d).
#include <gtest/gtest.h>

#include <cmath>

#include "tsubu/source/size_moments.hpp"

namespace tsubu {
namespace {

// Sample means of d and d^3 within 5 standard errors of the analytic ones.
void expect_moments(const SizeDistribution& dist, const std::string& what) {
  Random rng(3);
  const int n = 200000;
  double s1 = 0, s3 = 0;
  for (int k = 0; k < n; ++k) {
    const double d = dist.sample(rng);
    s1 += d;
    s3 += d * d * d;
  }
  for (double p : {1.0, 3.0}) {
    const double mean = mean_diameter_power(dist, p);
    const double sd = std::sqrt(mean_diameter_power(dist, 2 * p) - mean * mean);
    EXPECT_NEAR((p == 1 ? s1 : s3) / n, mean, 5 * sd / std::sqrt(n)) << what << ", E[d^" << p << "]";
  }
}

SizeDistribution talbot(double S, double Sigma, double d_max) {
  SizeDistribution d;
  d.kind = SizeDistribution::Kind::talbot;
  d.exponent = S;
  d.d_max = d_max;
  d.d_min = d_max * std::exp(-Sigma);  // Sigma = ln(d_max/d_min)
  return d;
}

TEST(SizeMoments, TalbotSamplerMatchesAnalyticMoments) {
  for (double S : {0.0, 1.0, 2.0, 3.0})
    for (double Sigma : {0.5, 2.0}) expect_moments(talbot(S, Sigma, 0.01), "S = " + std::to_string(S) + ", Sigma = " + std::to_string(Sigma));
}

TEST(SizeMoments, TalbotClosedFormsByHand) {
  const SizeDistribution d = talbot(2, 2.0, 0.01);  // n ∝ 1/d: E[d] = (b - a)/ln(b/a)
  EXPECT_NEAR(mean_diameter_power(d, 1), (d.d_max - d.d_min) / 2.0, 1e-15);
  const SizeDistribution d1 = talbot(1, 2.0, 0.01);  // n ∝ d^-2: E[d] = ln(b/a) / (1/a - 1/b)
  EXPECT_NEAR(mean_diameter_power(d1, 1), 2.0 / (1 / d1.d_min - 1 / d1.d_max), 1e-15);
  EXPECT_DOUBLE_EQ(mean_diameter_power(d, 0), 1.0);
}

TEST(SizeMoments, OtherDistributions) {
  SizeDistribution single;
  single.diameter = 0.002;
  EXPECT_DOUBLE_EQ(mean_grain_volume(single), M_PI / 6 * 8e-9);
  SizeDistribution uniform;
  uniform.kind = SizeDistribution::Kind::uniform;
  uniform.d_min = 0.001;
  uniform.d_max = 0.003;
  expect_moments(uniform, "uniform");
  SizeDistribution lognormal;
  lognormal.kind = SizeDistribution::Kind::lognormal;
  lognormal.median = 0.002;
  lognormal.sigma = 0.4;
  expect_moments(lognormal, "lognormal");
  EXPECT_NEAR(mean_diameter_power(lognormal, 1), 0.002 * std::exp(0.08), 1e-15);
  lognormal.d_min = 0.0015;
  lognormal.d_max = 0.004;
  expect_moments(lognormal, "truncated lognormal");
}

}  // namespace
}  // namespace tsubu
