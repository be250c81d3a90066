// Grain-size distributions (spec/sedimentation.md section 2). `sample` draws one diameter
// by the inverse CDF of the number density.
#pragma once
#include <cmath>
#include <stdexcept>

#include "tsubu/core/random.hpp"

namespace tsubu {

struct SizeDistribution {
  enum class Kind { single, uniform, lognormal, talbot };
  Kind kind = Kind::single;
  double diameter = 0;        // single, m
  double d_min = 0, d_max = 0;  // uniform, talbot; optional bounds of lognormal (0: none)
  double median = 0;          // lognormal: median diameter, m
  double sigma = 0;           // lognormal: standard deviation of ln d
  double exponent = 0;        // talbot: S in f(d) ∝ d^S (mass density), n(d) ∝ d^{S-3}

  double largest() const {
    switch (kind) {
      case Kind::single: return diameter;
      case Kind::lognormal: return d_max > 0 ? d_max : median * std::exp(6 * sigma);
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
    }
    return diameter;
  }
};

}  // namespace tsubu
