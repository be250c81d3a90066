// ExactSum (core/exact_sum.hpp): the correctly rounded sum of its terms, in any order.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "tsubu/core/exact_sum.hpp"

namespace tsubu {
namespace {

double exact_sum(const std::vector<double>& terms) {
  ExactSum s;
  for (double x : terms) s += x;
  return s.value();
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Sums whose rounded value is known: cancellation that a plain sum loses, terms a plain sum
// rounds away, and the ties that decide the last bit (1 + 2^-53 lies half-way between 1 and
// the next double: it rounds to the even 1, and any term beyond the tie breaks it upwards).
TEST(ExactSum, IsTheExactTotalRoundedOnce) {
  const double u = std::ldexp(1.0, -53);
  EXPECT_EQ(bits(exact_sum({})), bits(0.0));
  EXPECT_EQ(bits(exact_sum({-0.0, -0.0})), bits(0.0)) << "a sum of zeros is +0, as a plain sum from +0";
  EXPECT_EQ(exact_sum({1e16, 1.0, -1e16}), 1.0);
  EXPECT_EQ(exact_sum({1.0, 1e100, 1.0, -1e100}), 2.0);
  EXPECT_EQ(exact_sum({0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1}), 1.0);  // a plain sum gives 0.9999999999999999
  EXPECT_EQ(exact_sum({1.0, u}), 1.0);
  EXPECT_EQ(exact_sum({1.0, u, u * u}), 1.0 + 2 * u);
  EXPECT_EQ(exact_sum({1.0 + 2 * u, u}), 1.0 + 4 * u);  // the tie to the even neighbour above
  EXPECT_EQ(exact_sum({1.0, u, -u * u}), 1.0);
  EXPECT_EQ(exact_sum({std::numeric_limits<double>::max(), std::numeric_limits<double>::max()}), INFINITY);
  EXPECT_EQ(exact_sum({1.0, INFINITY, 2.0}), INFINITY);
  EXPECT_TRUE(std::isnan(exact_sum({INFINITY, 1.0, -INFINITY})));
  EXPECT_TRUE(std::isnan(exact_sum({1.0, NAN})));
}

// Energies of grains of sizes over three decades and potential energies of both signs: every
// order of the terms, and any split into parts summed apart and merged (threads, processes),
// gives the same bits, which agree with a sum in long double arithmetic (a 64-bit mantissa)
// to within 2 ulp; a plain sum of doubles moves with the order.
TEST(ExactSum, AnyOrderAndAnySplitGiveTheSameBits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> terms;
  for (int k = 0; k < 5000; ++k) terms.push_back(unit(rng) * std::pow(10.0, 9 * std::fabs(unit(rng))) * 1e-12);
  const double reference = exact_sum(terms);
  double plain = 0;
  for (double x : terms) plain += x;
  bool plain_moved = false;
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(terms.begin(), terms.end(), rng);
    EXPECT_EQ(bits(exact_sum(terms)), bits(reference));
    const std::size_t cut = static_cast<std::size_t>(rng() % terms.size());
    ExactSum first, second;
    for (std::size_t k = 0; k < terms.size(); ++k) (k < cut ? first : second) += terms[k];
    second += first;
    EXPECT_EQ(bits(second.value()), bits(reference));
    double shuffled = 0;
    for (double x : terms) shuffled += x;
    plain_moved = plain_moved || bits(shuffled) != bits(plain);
  }
  EXPECT_TRUE(plain_moved) << "the terms should be such that a plain sum depends on their order";
  long double wide = 0;
  for (double x : terms) wide += x;
  EXPECT_NEAR(reference, static_cast<double>(wide), 2 * std::fabs(reference) * std::numeric_limits<double>::epsilon());
}

}  // namespace
}  // namespace tsubu
