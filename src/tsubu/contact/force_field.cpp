#include "tsubu/contact/force_field.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/core/parallel.hpp"

namespace tsubu {

namespace {

// New contact list in the order of `found`, each carrying the history of the same key in
// `old` (both sorted by (i, j)) or a fresh one.
void carry_history(const std::vector<Pair>& found, const std::vector<Contact>& old, std::vector<Contact>& out) {
  out.resize(found.size());
  std::size_t o = 0;
  for (std::size_t k = 0; k < found.size(); ++k) {
    const Pair& f = found[k];
    while (o < old.size() && (old[o].i < f.i || (old[o].i == f.i && old[o].j < f.j))) ++o;
    out[k].i = f.i;
    out[k].j = f.j;
    out[k].touching = false;
    out[k].history = (o < old.size() && old[o].i == f.i && old[o].j == f.j) ? old[o].history : ContactHistory{};
  }
}

// Runs kernel(k, normal_model, tangential_model) for contacts k = 0..n-1 in parallel.
// With one pair of model types for the whole table the dispatch happens once, outside the
// loop; otherwise once per contact through a jump table (never a virtual call).
template <class LawOf, class Kernel>
void for_each_contact(const LawTable& laws, std::size_t n, LawOf law_of, Kernel kernel) {
  if (laws.uniform()) {
    std::visit(
        [&](const auto& n0, const auto& t0) {
          using N = std::decay_t<decltype(n0)>;
          using T = std::decay_t<decltype(t0)>;
          parallel_for(n, [&](std::size_t k) {
            const PairLaw& law = law_of(k);
            kernel(k, *std::get_if<N>(&law.normal), *std::get_if<T>(&law.tangential));
          });
        },
        laws.laws.front().normal, laws.laws.front().tangential);
  } else {
    parallel_for(n, [&](std::size_t k) {
      const PairLaw& law = law_of(k);
      std::visit([&](const auto& nm, const auto& tm) { kernel(k, nm, tm); }, law.normal, law.tangential);
    });
  }
}

}  // namespace

void ForceField::compute(World& world) {
  if (needs_rebuild(world)) rebuild(world);
  evaluate_pairs(world);
  evaluate_walls(world);
  accumulate(world);
}

bool ForceField::needs_rebuild(const World& world) const {
  const Particles& p = world.particles;
  if (built_at_.size() != p.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (norm2(world.domain.separation(p.position[i], built_at_[i])) > limit2) return true;
  return false;
}

void ForceField::rebuild(World& world) {
  const Particles& p = world.particles;
  skin_ = world.skin;
  if (skin_ <= 0 && p.size() > 0) skin_ = 0.2 * *std::min_element(p.radius.begin(), p.radius.end());
  grid_.find_pairs(p, world.domain, skin_, candidates_);
  carry_history(candidates_, world.pair_contacts, next_);
  world.pair_contacts.swap(next_);
  find_wall_contacts(world, candidates_);
  carry_history(candidates_, world.wall_contacts, next_);
  world.wall_contacts.swap(next_);
  built_at_ = p.position;
  ++rebuilds_;
}

void ForceField::find_wall_contacts(const World& world, std::vector<Pair>& out) {
  out.clear();
  if (world.walls.empty()) return;
  const Particles& p = world.particles;
  const int threads = threads_for(p.size());
  wall_hits_.resize(static_cast<std::size_t>(threads));
  for_each_thread(threads, [&](int t) {
    auto& local = wall_hits_[static_cast<std::size_t>(t)];
    local.clear();
    const auto [begin, end] = static_range(p.size(), t, threads);
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t w = 0; w < world.walls.size(); ++w) {
        // Within the skin on the front side; see evaluate_walls for the back side.
        const double dist = world.walls[w].distance(p.position[i]);
        if (dist < p.radius[i] + skin_ && dist > -p.radius[i] - skin_)
          local.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(w)});
      }
  });
  for (const auto& local : wall_hits_) out.insert(out.end(), local.begin(), local.end());
}

void ForceField::evaluate_pairs(World& world) {
  const Particles& p = world.particles;
  auto& contacts = world.pair_contacts;
  pair_results_.resize(contacts.size());
  const double dt = world.dt;
  auto law_of = [&](std::size_t k) -> const PairLaw& {
    return world.laws.at(p.material[contacts[k].i], p.material[contacts[k].j]);
  };
  for_each_contact(world.laws, contacts.size(), law_of, [&](std::size_t k, const auto& normal, const auto& tangential) {
    Contact& c = contacts[k];
    const std::size_t i = c.i, j = c.j;
    const Vec3 d = world.domain.separation(p.position[i], p.position[j]);
    const double ri = p.radius[i], rj = p.radius[j];
    const double dist2 = norm2(d);
    c.touching = dist2 < (ri + rj) * (ri + rj);
    if (!c.touching) {
      c.history = {};
      return;
    }
    const double dist = std::sqrt(dist2);
    ContactGeometry g;
    g.n = d / dist;
    g.delta = ri + rj - dist;
    const double arm_i = ri - 0.5 * g.delta, arm_j = rj - 0.5 * g.delta;
    const Vec3 v_rel = p.velocity[i] - p.velocity[j] + cross(p.omega[i], -arm_i * g.n) - cross(p.omega[j], arm_j * g.n);
    g.v_n = dot(v_rel, g.n);
    g.v_t = v_rel - g.v_n * g.n;
    g.r_eff = ri * rj / (ri + rj);
    g.m_eff = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
    g.d_mean = ri + rj;
    g.dt = dt;
    const ContactForce f = evaluate(normal, tangential, g, c.history);
    const Vec3 n_x_ft = cross(g.n, f.tangential);
    pair_results_[k] = {f.total, -arm_i * n_x_ft, -arm_j * n_x_ft, f.energy, g.delta / (2.0 * std::min(ri, rj))};
  });
}

void ForceField::evaluate_walls(World& world) {
  const Particles& p = world.particles;
  auto& contacts = world.wall_contacts;
  wall_results_.resize(contacts.size());
  const double dt = world.dt;
  auto law_of = [&](std::size_t k) -> const PairLaw& {
    return world.laws.at(p.material[contacts[k].i], world.walls[contacts[k].j].material);
  };
  for_each_contact(world.laws, contacts.size(), law_of, [&](std::size_t k, const auto& normal, const auto& tangential) {
    Contact& c = contacts[k];
    const std::size_t i = c.i;
    const Wall& wall = world.walls[c.j];
    const double ri = p.radius[i];
    const double dist = wall.distance(p.position[i]);
    // Touching from the front side only: a centre behind the plane has tunnelled through.
    c.touching = dist < ri && dist > -ri;
    if (!c.touching) {
      c.history = {};
      return;
    }
    ContactGeometry g;
    g.n = wall.normal;
    g.delta = ri - dist;
    const double arm_i = ri - 0.5 * g.delta;
    const Vec3 v_rel = p.velocity[i] + cross(p.omega[i], -arm_i * g.n);
    g.v_n = dot(v_rel, g.n);
    g.v_t = v_rel - g.v_n * g.n;
    g.r_eff = ri;
    g.m_eff = p.mass[i];
    g.d_mean = 2.0 * ri;
    g.dt = dt;
    const ContactForce f = evaluate(normal, tangential, g, c.history);
    wall_results_[k] = {f.total, -arm_i * cross(g.n, f.tangential), {}, f.energy, g.delta / (2.0 * ri)};
  });
}

void ForceField::accumulate(World& world) {
  Particles& p = world.particles;
  const std::size_t n = p.size();
  parallel_for(n, [&](std::size_t i) {
    p.force[i] = p.mass[i] * world.gravity;
    p.torque[i] = {};
    p.contact_count[i] = 0;
  });
  // Serial, in contact order: the sums are the same bits for every thread count.
  ContactTotals totals;
  const Contact* worst = nullptr;
  bool worst_is_wall = false;
  auto add = [&](const Contact& c, const Result& r, bool wall) {
    if (!c.touching) return;
    ++totals.contacts;
    p.force[c.i] += r.force_i;
    p.torque[c.i] += r.torque_i;
    ++p.contact_count[c.i];
    if (!wall) {
      p.force[c.j] -= r.force_i;
      p.torque[c.j] += r.torque_j;
      ++p.contact_count[c.j];
    }
    totals.elastic_energy += r.energy;
    if (r.overlap_ratio > totals.max_overlap_ratio || !std::isfinite(r.force_i.x + r.force_i.y + r.force_i.z)) {
      totals.max_overlap_ratio = std::max(totals.max_overlap_ratio, r.overlap_ratio);
      worst = &c;
      worst_is_wall = wall;
      if (!std::isfinite(r.force_i.x + r.force_i.y + r.force_i.z)) totals.max_overlap_ratio = INFINITY;
    }
  };
  for (std::size_t k = 0; k < world.pair_contacts.size(); ++k) add(world.pair_contacts[k], pair_results_[k], false);
  for (std::size_t k = 0; k < world.wall_contacts.size(); ++k) add(world.wall_contacts[k], wall_results_[k], true);
  evaluations_ += totals.contacts;
  totals_ = totals;
  if (worst && !(totals.max_overlap_ratio <= world.overlap_limit)) {
    std::ostringstream msg;
    msg << "step " << world.step << ", t = " << world.time << " s: contact between particle id "
        << p.id[worst->i] << " and " << (worst_is_wall ? "wall " + std::to_string(worst->j) : "particle id " + std::to_string(p.id[worst->j]))
        << " has overlap/diameter " << totals.max_overlap_ratio << " (limit " << world.overlap_limit
        << ", simulation.overlap_limit); the time step " << world.dt
        << " s is probably too large for this stiffness and impact speed: try dt/4";
    throw NumericalError(msg.str());
  }
}

}  // namespace tsubu
