#include "tsubu/sim/outflow.hpp"

#include <algorithm>
#include <utility>

#include "tsubu/world/spatial_sort.hpp"

namespace tsubu {

std::vector<Departure> Outflow::departures(const World& w, std::size_t count) {
  const Particles& p = w.particles;
  std::vector<Departure> gone;
  for (std::size_t i = 0; i < count; ++i)
    if (const int face = w.domain.departed(p.position[i]); face >= 0)
      gone.push_back({w.step, w.time, p.id[i], 2 * p.radius[i], p.mass[i], p.position[i], p.velocity[i], face});
  std::sort(gone.begin(), gone.end(), [](const Departure& a, const Departure& b) { return a.id < b.id; });
  return gone;
}

void Outflow::record(const std::vector<Departure>& gone) {
  for (const Departure& d : gone) {
    pending_.push_back(d);
    ++totals_.count;
    totals_.mass += d.mass;
    if (d.id >= inflow_first_id_) totals_.inflow_mass += d.mass;
  }
}

bool Outflow::remove_departed(World& w, std::vector<std::uint32_t>* kept) {
  const std::vector<Departure> gone = departures(w, w.particles.size());
  if (gone.empty()) return false;
  record(gone);
  const Particles& p = w.particles;
  std::vector<char> flags(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) flags[i] = w.domain.departed(p.position[i]) >= 0;
  std::vector<std::uint32_t> order = remove_particles(w, flags);
  if (kept) *kept = std::move(order);
  return true;
}

void Outflow::follow(Outflow& source) {
  totals_ = source.totals_;
  for (Departure& d : source.take_departures()) pending_.push_back(d);
}

}  // namespace tsubu
