// Characteristic sizes of a set of grains by mass, as sediment labs report them: D_q is the
// diameter below which the fraction q of the mass lies.
#pragma once
#include <vector>

#include "tsubu/world/world.hpp"

namespace tsubu {

struct MassPercentiles {
  double d10 = 0, d50 = 0, d90 = 0;  // m
};

struct SizedGrain {
  double diameter = 0;  // m
  double mass = 0;      // kg (any unit: only the shares count)
};

// D10, D50, D90 of the grains: after sorting by diameter, D_q is the diameter of the first
// grain at which the cumulative mass reaches q of the total. No grain: NaN for all three.
MassPercentiles mass_percentiles(std::vector<SizedGrain> grains);

// For every [[particles]] source (World::source_ids), in the order of the scenario: the
// grains it has given so far and their sizes. Empty for a world without source ids (a
// resumed run's).
struct SourceSizes {
  long grains = 0;
  MassPercentiles sizes;
};
std::vector<SourceSizes> source_sizes(const World& w);

}  // namespace tsubu
