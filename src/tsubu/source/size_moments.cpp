#include "tsubu/source/size_moments.hpp"

#include <cmath>
#include <limits>

namespace tsubu {

namespace {

// ∫_a^b d^q dd.
double power_integral(double a, double b, double q) {
  if (std::abs(q + 1) < 1e-12) return std::log(b / a);
  return (std::pow(b, q + 1) - std::pow(a, q + 1)) / (q + 1);
}

// Standard normal CDF.
double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

}  // namespace

double mean_diameter_power(const SizeDistribution& s, double p) {
  switch (s.kind) {
    case SizeDistribution::Kind::single: return std::pow(s.diameter, p);
    case SizeDistribution::Kind::uniform: return power_integral(s.d_min, s.d_max, p) / (s.d_max - s.d_min);
    case SizeDistribution::Kind::talbot:
      return power_integral(s.d_min, s.d_max, s.exponent - 3 + p) / power_integral(s.d_min, s.d_max, s.exponent - 3);
    case SizeDistribution::Kind::table: {  // number density ∝ c_k d^-3 per unit ln d in interval k
      double moment = 0, count = 0;
      for (std::size_t k = 0; k + 1 < s.sieve.size(); ++k) {
        const double a = s.sieve[k], b = s.sieve[k + 1], c = (s.finer[k + 1] - s.finer[k]) / std::log(b / a);
        moment += c * power_integral(a, b, p - 4);
        count += c * power_integral(a, b, -4);
      }
      return moment / count;
    }
    case SizeDistribution::Kind::lognormal: {
      const double inf = std::numeric_limits<double>::infinity();
      const double alpha = s.d_min > 0 ? std::log(s.d_min / s.median) / s.sigma : -inf;
      const double beta = s.d_max > 0 ? std::log(s.d_max / s.median) / s.sigma : inf;
      const double ps = p * s.sigma;
      return std::pow(s.median, p) * std::exp(0.5 * ps * ps) * (normal_cdf(beta - ps) - normal_cdf(alpha - ps)) /
             (normal_cdf(beta) - normal_cdf(alpha));
    }
  }
  return 0;
}

double mean_grain_volume(const SizeDistribution& sizes) { return M_PI / 6 * mean_diameter_power(sizes, 3); }

}  // namespace tsubu
