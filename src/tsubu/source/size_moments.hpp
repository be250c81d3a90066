// Moments of the number distribution of a grain-size distribution, in closed form: the
// mean of d^p over n(d) (docs/sedimentation.md). They give the grains per second
// of a mass flux (mean grain volume) and check the samplers.
#pragma once
#include "tsubu/core/size_distribution.hpp"

namespace tsubu {

// E[d^p] over the number density n(d) of `sizes`, m^p:
//   single: d^p; uniform: (b^{p+1} - a^{p+1}) / ((p+1)(b-a));
//   talbot: n ∝ d^{S-3} on [a, b], E[d^p] = I(S-3+p) / I(S-3), I(q) = ∫_a^b d^q dd
//           (ln(b/a) for q = -1: S = 2 when p = 0, and S = 1 - p in general);
//   lognormal with median m and ln-spread s, truncated to [a, b] where bounds are set:
//     m^p exp(p^2 s^2/2) [Phi(beta - p s) - Phi(alpha - p s)] / [Phi(beta) - Phi(alpha)],
//     alpha = ln(a/m)/s, beta = ln(b/m)/s (a missing bound is -inf or +inf);
//   table: n ∝ c_k d^-4 per unit d on sieve interval k, E[d^p] = sum c_k I_k(p-4) / sum c_k I_k(-4).
double mean_diameter_power(const SizeDistribution& sizes, double p);

// The mean volume pi/6 E[d^3] of one grain, m^3.
double mean_grain_volume(const SizeDistribution& sizes);

}  // namespace tsubu
