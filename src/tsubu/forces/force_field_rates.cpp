// ForceField's evaluation of an active set with rates (block-step Hermite): the same lists,
// contact evaluation (forces/evaluate.hpp, on Dual numbers) and gather as the fixed steps.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "tsubu/core/bytes.hpp"
#include "tsubu/core/parallel.hpp"
#include "tsubu/forces/evaluate.hpp"
#include "tsubu/forces/force_field.hpp"
#include "tsubu/forces/gather.hpp"

namespace tsubu {

void ForceField::compute_active(World& world, const Predictor& kin, const std::vector<std::uint32_t>& active,
                                const std::vector<char>& is_active, const ContactStepRules& rules, EvaluationRates& out) {
  check_overlaps(world, evaluate_active(world, kin, active, is_active, is_active, rules, out));
}

double ForceField::evaluate_active(World& world, const Predictor& kin, std::span<const std::uint32_t> active,
                                   const std::vector<char>& is_active, const std::vector<char>& here,
                                   const ContactStepRules& rules, EvaluationRates& out) {
  if (!without_rates_.empty())
    throw std::invalid_argument("the " + without_rates_ + " has no rates: block steps cannot evaluate it");
  Particles& p = world.particles;
  admit_new_particles(p);
  const ContactList& contacts = world.contacts;
  const auto& pairs = contacts.pairs();
  const auto& walls = contacts.walls();
  pair_results_.resize(pairs.size(), false, rolls_);
  wall_results_.resize(walls.size(), false, rolls_);
  pair_rates_.resize(pairs.size());
  wall_rates_.resize(walls.size());
  // Each contact once, from its first active particle here; contacts of different active
  // particles are disjoint, so the active list can be split between threads. An active
  // particle's pairs go in blocks, each pair with its own law.
  const PredictedState state{kin};
  // With meshes, where the active particles touch the walls at the predicted positions: every
  // listed triangle asked (its gap for the step rules), not only those within the radius.
  if (!world.wall_elements.empty()) {
    wall_touch_.resize(walls.size());
    parallel_for(active.size(), [&](std::size_t q) {
      touch_particle_walls(world, active[q], kin.at(active[q]).x, INFINITY);
    });
  }
  parallel_for(active.size(), [&](std::size_t q) {
    std::uint32_t block[kBlock];
    std::size_t m = 0;
    contacts.for_each_contact_of(active[q], [&](std::uint32_t k, auto side) {
      if (side == 0) {
        evaluate_wall(world, state, k, &rules);
      } else if (side > 0 || !here[pairs[k].i]) {
        block[m++] = k;
        if (m == kBlock) evaluate_pair_block(world, state, ListIndices{block, m}, pair_law_, &rules), m = 0;
      }
    });
    if (m > 0) evaluate_pair_block(world, state, ListIndices{block, m}, pair_law_, &rules);
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
    // The dashpots: the fastest decay rate of the dashpots around particle i is at most
    // sum_c max(eta_n, (7/2) eta_t) (1/m_i + 1/sqrt(m_i m_j)) (block Gershgorin on
    // M^-1/2 C M^-1/2: contact c's dashpot acts on the relative velocity of i and j at the
    // contact point, along its normal with eta_n and along the contact plane with eta_t,
    // where it moves sliding and rolling at once, 1/m + R^2/I = 7/(2m) for a sphere, so its
    // block of particle i has the norm max(eta_n, 7/2 eta_t)/m_i; a wall has m_j = infinity;
    // model EPSD's rolling dashpot adds C_r (1/I_i + 1/sqrt(I_i I_j)) for the spins).
    // For an isolated pair of equal grains with eta_t = eta_n this is the exact rate
    // 7 eta/m of their relative sliding; with n contacts it grows n-fold. The Hermite
    // corrector is stable for a decay rate lambda while lambda h < 2.5 (amplification
    // 1 + z + z^2/2 + z^3/6, z = -lambda h): the integrator's dashpot rule.
    out.damping_rate[i] = g.damping_over_mass;
    worst[q] = std::isfinite(g.force.x + g.force.y + g.force.z) ? g.deepest / (2.0 * r) : INFINITY;
    touching[q] = g.evaluated;
    p.force[i] = g.force;
    p.torque[i] = g.torque;
    p.contact_count[i] = g.count + g.own;
    out.force[i] = g.force_rate;
    out.torque[i] = g.torque_rate;
    out.step_bound[i] = g.bound;
    out.touched_for[i] = g.began == 1 && g.ended == 0 ? g.touched_for : 0.0;
    out.released_for[i] = g.ended == 1 && g.began == 0 ? g.released_for : 0.0;
  });
  active_evaluations_ = 0;
  for (std::uint64_t c : touching) active_evaluations_ += c;
  evaluations_ += active_evaluations_;
  started_ = true;
  return worst.empty() ? 0.0 : *std::max_element(worst.begin(), worst.end());
}

void ForceField::check_overlaps(const World& world, double worst) const {
  if (!(worst <= model_->overlap_limit)) report_overlap(world, true);
}

namespace {
static_assert(std::is_trivially_copyable_v<ContactHistory>);
}  // namespace

// A contact's record in pack_active: its kind (a pair or a wall, apart or touching), its index
// and, when it touches, its history, result and the rates the dashpots' response reads (the
// others are read only by the gather of the process that evaluated it). A contact apart has
// the empty history and zero results the evaluation gave it.
enum ContactRecordKind : char { kPairApart, kPairTouching, kWallApart, kWallTouching };

void ForceField::pack_active(const World& world, std::span<const std::uint32_t> mine, const std::vector<char>& is_active,
                             std::string& out) const {
  const Particles& p = world.particles;
  const ContactList& contacts = world.contacts;
  const bool crowds = !crowd_list_.empty(), meshes = !world.wall_elements.empty();
  put(out, active_evaluations_);
  put(out, static_cast<std::uint64_t>(mine.size()));
  for (std::uint32_t i : mine) {
    put(out, i), put(out, p.force[i]), put(out, p.torque[i]), put(out, p.contact_count[i]);
    if (crowds) put(out, crowding_[i]);
  }
  const std::size_t count_at = out.size();  // the contacts' count, written once known
  std::uint64_t link_count = 0;
  put(out, link_count);
  for (std::uint32_t i : mine)
    contacts.for_each_contact_of(i, [&](std::uint32_t k, auto side) {
      if (side < 0 && is_active[contacts.pairs()[k].i]) return;  // its first particle's process sends it
      const bool wall = side == 0;
      const Contact& c = wall ? contacts.walls()[k] : contacts.pairs()[k];
      put(out, static_cast<char>(wall ? (c.touching ? kWallTouching : kWallApart) : (c.touching ? kPairTouching : kPairApart)));
      put(out, k);
      if (wall && meshes) put(out, wall_touch_[k]);
      ++link_count;
      if (!c.touching) return;
      const Results& res = wall ? wall_results_ : pair_results_;
      const Rates& rt = wall ? wall_rates_[k] : pair_rates_[k];
      put(out, c.history), put(out, res.entry[k]);
      put(out, rt.n), put(out, rt.damping), put(out, rt.tangential_damping), put(out, rt.rolling_damping);
      if (rolls_) put(out, res.rolling_i[k]);
    });
  std::memcpy(out.data() + count_at, &link_count, sizeof link_count);
}

void ForceField::take_active(World& world, std::string_view bytes, std::size_t& at) {
  Particles& p = world.particles;
  ContactList& contacts = world.contacts;
  const bool crowds = !crowd_list_.empty(), meshes = !world.wall_elements.empty();
  evaluations_ += take<std::uint64_t>(bytes, at);
  for (auto n = take<std::uint64_t>(bytes, at); n > 0; --n) {
    const auto i = take<std::uint32_t>(bytes, at);
    p.force[i] = take<Vec3>(bytes, at), p.torque[i] = take<Vec3>(bytes, at), p.contact_count[i] = take<int>(bytes, at);
    if (crowds) crowding_[i] = take<Crowding>(bytes, at);
  }
  for (auto n = take<std::uint64_t>(bytes, at); n > 0; --n) {
    const auto kind = take<char>(bytes, at);
    const auto k = take<std::uint32_t>(bytes, at);
    const bool wall = kind == kWallApart || kind == kWallTouching;
    if (wall && meshes) wall_touch_[k] = take<ElementTouch>(bytes, at);
    Contact& c = wall ? contacts.walls()[k] : contacts.pairs()[k];
    Results& res = wall ? wall_results_ : pair_results_;
    Rates& rt = wall ? wall_rates_[k] : pair_rates_[k];
    c.touching = kind == kWallTouching || kind == kPairTouching;
    if (!c.touching) {
      c.history = {}, res.entry[k] = {};
      if (rolls_) res.rolling_i[k] = {};
      continue;
    }
    c.history = take<ContactHistory>(bytes, at), res.entry[k] = take<ContactResult>(bytes, at);
    rt.n = take<Vec3>(bytes, at), rt.damping = take<double>(bytes, at), rt.tangential_damping = take<double>(bytes, at);
    rt.rolling_damping = take<double>(bytes, at);
    if (rolls_) res.rolling_i[k] = take<Vec3>(bytes, at);
  }
}

void ForceField::dashpot_response(const World& world, const std::vector<std::uint32_t>& active,
                                  const std::vector<Vec3>& dv, const std::vector<Vec3>& dw, std::vector<Vec3>& df,
                                  std::vector<Vec3>& dtorque) const {
  const Particles& p = world.particles;
  const ContactList& contacts = world.contacts;
  parallel_for(active.size(), [&](std::size_t q) {
    const std::uint32_t i = active[q];
    Vec3 force, torque;
    contacts.for_each_contact_of(i, [&](std::uint32_t c, auto side) {
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
      if (rt.rolling_damping > 0) {  // model EPSD's dashpot, -C_r w_r on a, as the rolling torque
        const Vec3 dw_rel = side == 0 ? dw[a] : dw[a] - dw[k.j];
        torque += sign * (-rt.rolling_damping) * (dw_rel - dot(dw_rel, rt.n) * rt.n);
      }
    });
    df[i] = force;
    dtorque[i] = torque;
  });
}

}  // namespace tsubu
