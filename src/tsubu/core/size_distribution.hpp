// Grain-size distributions (docs/sedimentation.md). `sample` draws one diameter
// by the inverse CDF of the number density.
#pragma once
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "tsubu/core/random.hpp"

namespace tsubu {

struct SizeDistribution {
  enum class Kind { single, uniform, lognormal, talbot, table };
  Kind kind = Kind::single;
  double diameter = 0;        // single, m
  double d_min = 0, d_max = 0;  // uniform, talbot; optional bounds of lognormal (0: none)
  double median = 0;          // lognormal: median diameter, m
  double sigma = 0;           // lognormal: standard deviation of ln d
  double exponent = 0;        // talbot: S in f(d) ∝ d^S (mass density), n(d) ∝ d^{S-3}
  // table: a sieve curve, the mass fraction finer than sieve[k] is finer[k] (both
  // increasing, finer from 0 to 1). Between two sieves the mass fraction is linear in ln d:
  // a constant mass density c_k per unit ln d, hence a number density ∝ c_k d^-3 per unit
  // ln d. number_weight[k] is the share of the grains (by number) in interval k.
  std::vector<double> sieve, finer, number_weight;

  // Fills number_weight from sieve and finer: interval k holds
  // c_k ∫ d^-3 dln d = c_k (d_k^-3 - d_{k+1}^-3) / 3, normalised.
  void weigh_table() {
    number_weight.assign(sieve.size() - 1, 0.0);
    double total = 0;
    for (std::size_t k = 0; k + 1 < sieve.size(); ++k) {
      const double c = (finer[k + 1] - finer[k]) / std::log(sieve[k + 1] / sieve[k]);
      number_weight[k] = c * (std::pow(sieve[k], -3) - std::pow(sieve[k + 1], -3)) / 3;
      total += number_weight[k];
    }
    for (double& w : number_weight) w /= total;
  }

  double smallest() const {
    switch (kind) {
      case Kind::single: return diameter;
      case Kind::lognormal: return d_min > 0 ? d_min : median * std::exp(-6 * sigma);
      case Kind::table: return sieve.front();
      default: return d_min;
    }
  }

  double largest() const {
    switch (kind) {
      case Kind::single: return diameter;
      case Kind::lognormal: return d_max > 0 ? d_max : median * std::exp(6 * sigma);
      case Kind::table: return sieve.back();
      default: return d_max;
    }
  }

  // Lognormal: the fraction of draws within the optional bounds (the rest are rejected). The
  // loader refuses bounds that keep less than kMinAcceptance (a median typed in mm), so the
  // rejection loop of sample() needs about 1/acceptance draws and never reaches kMaxDraws.
  static constexpr double kMinAcceptance = 1e-3;
  static constexpr int kMaxDraws = 1000000;
  double acceptance() const {
    auto below = [&](double d) { return 0.5 * std::erfc(-std::log(d / median) / (sigma * std::sqrt(2.0))); };
    return (d_max > 0 ? below(d_max) : 1.0) - (d_min > 0 ? below(d_min) : 0.0);
  }

  double sample(Random& rng) const {
    switch (kind) {
      case Kind::single: return diameter;
      case Kind::uniform: return rng.uniform(d_min, d_max);
      case Kind::lognormal:
        for (int draw = 0; draw < kMaxDraws; ++draw) {  // rejection outside the optional bounds
          const double d = median * std::exp(sigma * rng.normal());
          if ((d_min <= 0 || d >= d_min) && (d_max <= 0 || d <= d_max)) return d;
        }
        throw std::runtime_error("no lognormal diameter within [d_min, d_max] in a million draws");
      case Kind::talbot: {
        const double u = rng.uniform();
        const double k = exponent - 2.0;  // integral of d^{S-3} is d^{S-2}/(S-2)
        if (std::abs(k) < 1e-12) return d_min * std::pow(d_max / d_min, u);  // S = 2: n ∝ 1/d
        const double a = std::pow(d_min, k), b = std::pow(d_max, k);
        return std::pow(a + u * (b - a), 1.0 / k);
      }
      case Kind::table: {  // one uniform number picks the interval and the place in it
        double u = rng.uniform();
        std::size_t k = 0;
        while (k + 1 < number_weight.size() && (u >= number_weight[k] || number_weight[k] == 0)) u -= number_weight[k++];
        while (number_weight[k] == 0) --k;  // round-off carried u past the last interval with grains
        const double share = std::clamp(u / number_weight[k], 0.0, 1.0);  // inverse CDF of d^-3 in interval k
        const double a = std::pow(sieve[k], -3), b = std::pow(sieve[k + 1], -3);
        return std::pow(a - share * (a - b), -1.0 / 3);
      }
    }
    return diameter;
  }
};

}  // namespace tsubu
