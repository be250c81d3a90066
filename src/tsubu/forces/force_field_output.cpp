// ForceField's view of its contacts for output: read from the stored results after an
// evaluation, outside the stepping loop.
#include "tsubu/forces/force_field.hpp"

namespace tsubu {

std::vector<ContactRecord> ForceField::touching_contacts(const World& world) const {
  const Particles& p = world.particles;
  std::vector<ContactRecord> out;
  auto add = [&](const Contact& c, const Results::Entry& e, bool wall, const Vec3& n) {
    // n x F_t with F_t in the tangent plane: F_t = (n x F_t) x n.
    const Vec3 tangential = cross(e.n_x_ft, n);
    out.push_back({c.i, c.j, wall, e.force_i - tangential, tangential, e.delta, c.history});
  };
  const std::vector<Contact>& pairs = world.contacts.pairs();
  const std::vector<Contact>& walls = world.contacts.walls();
  for (std::size_t k = 0; k < pairs.size() && k < pair_results_.entry.size(); ++k) {
    const Contact& c = pairs[k];
    if (!c.touching) continue;
    const Vec3 d = world.domain.separation(p.position[c.i], p.position[c.j]);
    add(c, pair_results_.entry[k], false, d / norm(d));
  }
  for (std::size_t k = 0; k < walls.size() && k < wall_results_.entry.size(); ++k) {
    const Contact& c = walls[k];
    if (!c.touching) continue;
    WallTouch touch;  // where it touched at the evaluation (a touching mesh contact counts there)
    world.touch_element(c.j, p.position[c.i], touch);
    add(c, wall_results_.entry[k], true, touch.normal);
  }
  return out;
}

}  // namespace tsubu
