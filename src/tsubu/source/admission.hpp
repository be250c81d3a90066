// Grains due from a stream (the inflow's column, source/inflow.hpp; an insertion,
// source/insertion.hpp) enter the box at a step boundary: each at its place, unless the
// place is taken, when it goes back to the stream to wait (delay()): never dropped, never
// overlapped.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "tsubu/source/inflow.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

// What admit_due() did at one time.
struct Admission {
  std::size_t entered = 0, delayed = 0;
};

// In a run split among processes: makes "the place of due grain k is taken" (one flag each,
// in the order of due()) that of any process (an elementwise or).
using OverlapAgreement = std::function<void(std::vector<char>& taken)>;

// Inserts the grains due at time t into `into` (of `material`, the stream's density), each
// at stream.position(g, t) with the stream's velocity and the grain's spin, id = first_id +
// serial. A grain whose place is taken (it would overlap one of the first `seen` particles
// of `present`, or one inserted just before it, or the stream finds it too near a wall)
// goes back to the stream with delay(). `domain` gives the periodic sides. With `agree`
// (a split run: `present` is a process's own particles), every process admits the same
// grains and leaves its stream in the same state.
template <class Stream>
Admission admit_due(Stream& stream, double t, const Domain& domain, std::span<const Wall> walls, const Particles& present,
                    std::size_t seen, Particles& into, int material, std::int64_t first_id, const OverlapAgreement& agree) {
  Admission a;
  const std::vector<NewGrain> due = stream.due(t);
  if (due.empty()) return a;
  SphereGrid grid = stream.neighbours(domain, std::span(present.position).first(seen), std::span(present.radius).first(seen),
                                      due, t);
  std::vector<char> taken(due.size());  // its place holds a particle already there
  for (std::size_t k = 0; k < due.size(); ++k) taken[k] = grid.overlaps(stream.position(due[k], t), 0.5 * due[k].diameter);
  if (agree) agree(taken);
  for (std::size_t k = 0; k < due.size(); ++k) {
    const NewGrain& g = due[k];
    const Vec3 x = stream.position(g, t);
    if (taken[k] || grid.overlaps(x, 0.5 * g.diameter) || !stream.clear_of_walls(x, 0.5 * g.diameter, walls)) {
      stream.delay(g);  // or one inserted just before it took the place
      ++a.delayed;
      continue;
    }
    grid.add(x, 0.5 * g.diameter);
    into.add(first_id + g.serial, material, g.diameter, stream.density(), x, stream.velocity());
    into.omega.back() = g.omega;
    ++a.entered;
  }
  return a;
}

// The same in one process: the grains enter `particles`.
template <class Stream>
Admission admit_due(Stream& stream, double t, const Domain& domain, Particles& particles, int material, std::int64_t first_id,
                    std::span<const Wall> walls = {}) {
  return admit_due(stream, t, domain, walls, particles, particles.size(), particles, material, first_id, {});
}

}  // namespace tsubu
