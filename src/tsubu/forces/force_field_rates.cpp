// ForceField's evaluation of an active set with rates (block-step Hermite): the same lists,
// contact laws (run on Dual numbers) and gather as the fixed-step evaluation.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/forces/gather.hpp"
#include "tsubu/contact/pair_geometry.hpp"
#include "tsubu/core/parallel.hpp"

namespace tsubu {

namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// The step a contact allows (ContactStepRules): touching, the shorter of kappa_c times its
// collision time at the current approach speed and half a period of its current stiffness;
// apart, the time to close the gap, never below the step it would get on touching. (The
// dashpots' bound is a particle's: see damping_rate.) The collision time (a fifth root for
// Hertz) is computed only when it is the bound.
template <class Normal>
double contact_step(const Normal& normal, const ContactStepRules& rules, double m_eff, double r_eff, bool touching,
                    double v_approach, const ContactForceRate* now, double gap, double a_approach) {
  const double u = std::max(v_approach, rules.u_floor);
  const auto impact = [&] { return rules.kappa_c * normal.collision_time(m_eff, r_eff, u); };
  if (!touching) {
    const double closing = rules.eta_gap * time_to_close(gap, v_approach, a_approach);
    return collision_longer_than(normal, m_eff, r_eff, u, closing / rules.kappa_c) ? impact() : closing;
  }
  if (!(now->stiffness > 0)) return impact();
  const double spring = rules.kappa_c * M_PI * std::sqrt(m_eff / now->stiffness);
  return collision_longer_than(normal, m_eff, r_eff, u, spring / rules.kappa_c) ? spring : impact();
}

// The law's models, for a law with rates (compute_active refuses a table with another).
template <class Visit>
void visit_law(const PairLaw& law, Visit&& visit) {
  std::visit(
      [&](const auto& normal, const auto& tangential) {
        if constexpr (has_rates_v<std::decay_t<decltype(normal)>>) visit(normal, tangential);
      },
      law.normal, law.tangential);
}

}  // namespace

template <class Normal, class Tangential>
void ForceField::evaluate_pair_rates(World& world, const Predictor& kin, std::size_t k, const ContactStepRules& rules,
                                     const Normal& normal, const Tangential& tangential) {
  const Particles& p = world.particles;
  Contact& c = world.contacts.pairs()[k];
  const Kinematics a = kin.at(c.i), b = kin.at(c.j);
  const Vec3 d = world.domain.separation(a.x, b.x);
  const double ri = p.radius[c.i], rj = p.radius[c.j], reach = ri + rj;
  const double dist = norm(d);
  const double m_eff = p.mass[c.i] * p.mass[c.j] / (p.mass[c.i] + p.mass[c.j]);
  const double r_eff = ri * rj / reach;
  c.touching = dist < reach;
  if (!c.touching) {
    c.history = {};
    pair_results_.set(k, {}, {}, 0, 0);
    const Vec3 n = d / dist;
    pair_rates_[k] = {{}, {}, 0,
                      contact_step(normal, rules, m_eff, r_eff, false, -dot(a.v - b.v, n), nullptr, dist - reach,
                                   -dot(a.a - b.a, n)), n};
    return;
  }
  DualContactGeometry g = pair_geometry<Dual>(ri, rj, p.mass[c.i], p.mass[c.j], DualVec3(d, a.v - b.v),
                                              DualVec3(a.v, a.a), DualVec3(b.v, b.a), DualVec3(a.w, a.alpha),
                                              DualVec3(b.w, b.alpha));
  g.dt = kin.since(std::max(kin.time[c.i], kin.time[c.j]));
  ContactHistory h = c.law_history(p);
  const ContactForceRate f = evaluate_with_rates(normal, tangential, g, h);
  c.set_law_history(p, h);
  const DualVec3 n_x_ft = cross(g.n, f.tangential);
  pair_results_.set(k, value(f.total), value(n_x_ft), g.delta.v, f.energy);
  pair_rates_[k] = {rate(f.total), rate(n_x_ft), g.delta.d,
                    contact_step(normal, rules, m_eff, r_eff, true, -g.v_n.v, &f, 0, 0), value(g.n), f.damping,
                    f.tangential_damping};
}

template <class Normal, class Tangential>
void ForceField::evaluate_wall_rates(World& world, const Predictor& kin, std::size_t k, const ContactStepRules& rules,
                                     const Normal& normal, const Tangential& tangential) {
  const Particles& p = world.particles;
  Contact& c = world.contacts.walls()[k];
  const Wall& wall = world.walls[c.j];
  const Kinematics a = kin.at(c.i);
  const double r = p.radius[c.i];
  const Vec3 v_rel = a.v - wall.velocity;
  const double dist = wall.distance(a.x);
  c.touching = dist < r && dist > 0;  // the front side only (see evaluate_walls)
  if (!c.touching) {
    c.history = {};
    wall_results_.set(k, {}, {}, 0, 0);
    const double bound = dist > 0 ? contact_step(normal, rules, p.mass[c.i], r, false, -dot(v_rel, wall.normal), nullptr,
                                                 dist - r, -dot(a.a, wall.normal))
                                  : kNever;
    wall_rates_[k] = {{}, {}, 0, bound, wall.normal};
    return;
  }
  const DualVec3 v_centre(v_rel, a.a);
  DualContactGeometry g = wall_geometry<Dual>(r, p.mass[c.i], wall.normal, Dual(dist, dot(v_rel, wall.normal)),
                                              v_centre, DualVec3(a.w, a.alpha));
  g.dt = kin.since(kin.time[c.i]);
  const ContactForceRate f = evaluate_with_rates(normal, tangential, g, c.history);
  const DualVec3 n_x_ft = cross(g.n, f.tangential);
  wall_results_.set(k, value(f.total), value(n_x_ft), g.delta.v, f.energy);
  wall_rates_[k] = {rate(f.total), rate(n_x_ft), g.delta.d,
                    contact_step(normal, rules, p.mass[c.i], r, true, -g.v_n.v, &f, 0, 0), wall.normal, f.damping,
                    f.tangential_damping};
}

void ForceField::compute_active(World& world, const Predictor& kin, const std::vector<std::uint32_t>& active,
                                const std::vector<char>& is_active, const ContactStepRules& rules, EvaluationRates& out) {
  if (!without_rates_.empty())
    throw std::invalid_argument("the normal model " + without_rates_ + " has no rates: block steps cannot evaluate it");
  Particles& p = world.particles;
  admit_new_particles(p);
  const ContactList& contacts = world.contacts;
  const auto& pairs = contacts.pairs();
  const auto& walls = contacts.walls();
  pair_results_.resize(pairs.size(), false);
  wall_results_.resize(walls.size(), false);
  pair_rates_.resize(pairs.size());
  wall_rates_.resize(walls.size());
  // Each contact once, from its first active particle; contacts of different active
  // particles are disjoint, so the active list can be split between threads.
  parallel_for(active.size(), [&](std::size_t q) {
    const std::uint32_t i = active[q];
    contacts.for_each_contact_of(i, [&](std::uint32_t k, int side) {
      if (side == 0) {
        const Contact& c = walls[k];
        visit_law(model_->laws.at(p.material[c.i], world.walls[c.j].material),
                  [&](const auto& n, const auto& t) { evaluate_wall_rates(world, kin, k, rules, n, t); });
      } else if (side > 0 || !is_active[pairs[k].i]) {
        const Contact& c = pairs[k];
        visit_law(model_->laws.at(p.material[c.i], p.material[c.j]),
                  [&](const auto& n, const auto& t) { evaluate_pair_rates(world, kin, k, rules, n, t); });
      }
    });
  });
  // Hindered settling: each active particle's crowding from the predicted neighbours.
  if (!crowd_list_.empty())
    parallel_for(active.size(), [&](std::size_t q) {
      const std::uint32_t i = active[q];
      crowding_[i] = crowd_list_.of<true>(world, i, [&](std::size_t j) {
        const Kinematics k = kin.at(j);
        return PointMotion{k.x, k.v};
      });
    });
  // The gather, as for fixed steps, with the rates beside the values.
  std::vector<double> worst(active.size(), 0.0);
  std::vector<std::uint64_t> touching(active.size(), 0);
  parallel_for(active.size(), [&](std::size_t q) {
    const std::uint32_t i = active[q];
    const double r = p.radius[i];
    Gathered<true> g;
    g.force = p.mass[i] * model_->gravity;
    // The fluid's forces depend on the velocity: the stepper adds them in its corrector,
    // where the corrected velocity is known (see BlockHermite::correct).
    gather<true>(world, i, g, &is_active);
    double bound = g.bound;
    // The dashpots: the fastest decay rate of the dashpots around particle i is at most
    // (7/2) sum_c eta_c (1/m_i + 1/sqrt(m_i m_j)) (Gershgorin on M^-1/2 C M^-1/2: the dashpot
    // of contact c acts on the relative velocity of i and j, and along the contact plane it
    // moves sliding and rolling at once, 1/m + R^2/I = 7/(2m) for a sphere; a wall has
    // m_j = infinity). For an isolated pair of equal grains this is the exact rate 7 eta/m
    // of their relative sliding; with n contacts it grows n-fold. The Hermite corrector is
    // stable for a decay rate lambda while lambda h < 2.5 (amplification 1 + z + z^2/2 +
    // z^3/6, z = -lambda h); the rule keeps lambda h <= eta_damping.
    if (g.damping_over_mass > 0) bound = std::min(bound, rules.eta_damping / (3.5 * g.damping_over_mass));
    worst[q] = std::isfinite(g.force.x + g.force.y + g.force.z) ? g.deepest / (2.0 * r) : INFINITY;
    touching[q] = g.evaluated;
    p.force[i] = g.force;
    p.torque[i] = g.torque;
    p.contact_count[i] = g.count + g.own;
    out.force[i] = g.force_rate;
    out.torque[i] = g.torque_rate;
    out.step_bound[i] = bound;
  });
  for (std::uint64_t c : touching) evaluations_ += c;
  const double max_ratio = worst.empty() ? 0.0 : *std::max_element(worst.begin(), worst.end());
  if (!(max_ratio <= model_->overlap_limit)) report_overlap(world, true);
}

void ForceField::dashpot_response(const World& world, const std::vector<std::uint32_t>& active,
                                  const std::vector<Vec3>& dv, const std::vector<Vec3>& dw, std::vector<Vec3>& df,
                                  std::vector<Vec3>& dtorque) const {
  const Particles& p = world.particles;
  const ContactList& contacts = world.contacts;
  parallel_for(active.size(), [&](std::size_t q) {
    const std::uint32_t i = active[q];
    Vec3 force, torque;
    contacts.for_each_contact_of(i, [&](std::uint32_t c, int side) {
      const Results& res = side == 0 ? wall_results_ : pair_results_;
      const Rates& rt = side == 0 ? wall_rates_[c] : pair_rates_[c];
      const double delta = res.entry[c].delta;
      if (!(delta > 0)) return;
      // The contact's first particle a (i itself for walls) and its partner b.
      const Contact& k = side == 0 ? contacts.walls()[c] : contacts.pairs()[c];
      const std::uint32_t a = k.i;
      const double arm_a = p.radius[a] - 0.5 * delta;
      const Vec3 du = side == 0 ? contact_point_velocity(rt.n, arm_a, 0.0, dv[a], dw[a], Vec3{})
                                : contact_point_velocity(rt.n, arm_a, p.radius[k.j] - 0.5 * delta, dv[a] - dv[k.j],
                                                         dw[a], dw[k.j]);
      const double du_n = dot(du, rt.n);
      const Vec3 df_t = -rt.tangential_damping * (du - du_n * rt.n);
      const double sign = side < 0 ? -1.0 : 1.0;  // i is the pair's j: the reaction
      force += sign * (-rt.damping * du_n * rt.n + df_t);
      torque += -(p.radius[i] - 0.5 * delta) * cross(rt.n, df_t);  // as Results::torque
    });
    df[i] = force;
    dtorque[i] = torque;
  });
}

}  // namespace tsubu
