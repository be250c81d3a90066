#include "tsubu/world/spatial_sort.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace tsubu {

namespace {

// The bits of v spread to every third bit (21 bits in, 63 out).
std::uint64_t spread(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

std::vector<std::uint32_t> sort_spatially(World& world) {
  Particles& p = world.particles;
  const std::size_t n = p.size();
  if (n < 2) return std::vector<std::uint32_t>(n, 0);
  const double cell = 2.0 * *std::min_element(p.radius.begin(), p.radius.end());
  constexpr double kMaxCell = (1 << 21) - 1;
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double c = std::clamp(std::floor((p.position[i][a] - world.domain.lower[a]) / cell), 0.0, kMaxCell);
      code |= spread(static_cast<std::uint64_t>(c)) << a;
    }
    key[i] = code;
  }
  std::vector<std::uint32_t> order(n);  // order[new] = old
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  p.for_each_array([&](auto& array) { permute(array, order); });

  std::vector<std::uint32_t> renumber(n);  // renumber[old] = new
  for (std::uint32_t k = 0; k < n; ++k) renumber[order[k]] = k;
  world.contacts.renumber(renumber, p);
  return order;
}

std::vector<std::uint32_t> remove_particles(World& world, const std::vector<char>& gone) {
  Particles& p = world.particles;
  const std::size_t n = p.size(), owned = world.owned();
  std::vector<std::uint32_t> new_index(n, ContactList::kGone), order;  // order[new] = old
  std::size_t ghosts = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (gone[i]) continue;
    new_index[i] = static_cast<std::uint32_t>(order.size());
    order.push_back(i);
    if (i >= owned) ++ghosts;
  }
  p.for_each_array([&](auto& array) {
    permute(array, order);
    array.resize(order.size());
  });
  world.ghosts = ghosts;
  world.contacts.renumber(new_index, p);
  return order;
}

}  // namespace tsubu
