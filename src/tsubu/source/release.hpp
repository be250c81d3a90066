// The bookkeeping the inflow's column (source/inflow.cpp) and an insertion
// (source/insertion.cpp) share: a grain's mass, the waiting grains handed out again, a grain
// turned back, and a grain released within the mass limit.
#pragma once
#include <cmath>
#include <vector>

#include "tsubu/source/inflow.hpp"

namespace tsubu {

inline double grain_mass(double density, double d) { return density * M_PI / 6 * d * d * d; }

// The grains waiting to enter, their arrival set to t; none waits after this.
inline std::vector<NewGrain> waiting_at(InflowStream::State& s, double t) {
  std::vector<NewGrain> out;
  for (NewGrain g : s.waiting) {
    g.arrival = t;
    out.push_back(g);
  }
  s.waiting.clear();
  return out;
}

// A grain that could not enter: it waits, counted.
inline void turn_back(InflowStream::State& s, NewGrain g) {
  if (g.delays++ == 0) ++s.delayed_grains;
  ++s.delays;
  s.waiting.push_back(g);
}

// Releases g (its serial is the count released so far) of mass m into `out` unless that would
// take the mass released beyond `mass_limit` (0: none), which stops the source; false then.
inline bool release(InflowStream::State& s, const NewGrain& g, double m, double mass_limit, std::vector<NewGrain>& out) {
  if (mass_limit > 0 && s.mass_released + m > mass_limit) {
    s.limit_reached = true;
    return false;
  }
  out.push_back(g);
  ++s.released;
  ++s.next;
  s.mass_released += m;
  return true;
}

}  // namespace tsubu
