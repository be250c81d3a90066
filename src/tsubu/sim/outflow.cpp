#include "tsubu/sim/outflow.hpp"

#include <algorithm>
#include <utility>

#include "tsubu/world/spatial_sort.hpp"

namespace tsubu {

bool Outflow::remove_departed(World& w, std::vector<std::uint32_t>* kept) {
  Particles& p = w.particles;
  const std::size_t n = p.size();
  std::vector<std::uint32_t> gone;
  for (std::uint32_t i = 0; i < n; ++i)
    if (w.domain.departed(p.position[i]) >= 0) gone.push_back(i);
  if (gone.empty()) return false;
  std::sort(gone.begin(), gone.end(), [&](std::uint32_t a, std::uint32_t b) { return p.id[a] < p.id[b]; });
  for (std::uint32_t i : gone) {
    pending_.push_back({w.step, w.time, p.id[i], 2 * p.radius[i], p.mass[i], p.position[i], p.velocity[i],
                        w.domain.departed(p.position[i])});
    ++totals_.count;
    totals_.mass += p.mass[i];
    if (p.id[i] >= inflow_first_id_) totals_.inflow_mass += p.mass[i];
  }
  std::vector<std::uint32_t> new_index(n, ContactList::kGone), order;  // order[new] = old
  order.reserve(n - gone.size());
  for (std::uint32_t i = 0; i < n; ++i)
    if (w.domain.departed(p.position[i]) < 0) new_index[i] = static_cast<std::uint32_t>(order.size()), order.push_back(i);
  p.for_each_array([&](auto& array) {
    permute(array, order);
    array.resize(order.size());
  });
  w.contacts.renumber(new_index, p);
  if (kept) *kept = std::move(order);
  return true;
}

}  // namespace tsubu
