#include "tsubu/integrate/block_hermite.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>

#include "tsubu/contact/pair_geometry.hpp"
#include "tsubu/core/bytes.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/core/parallel.hpp"
#include "tsubu/integrate/integrators.hpp"
#include "tsubu/world/spatial_sort.hpp"

namespace tsubu {

namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();
// Over a step in which a contact ended, j1 is trusted while |j1 - j0| h <= kJerkTrust |a1 - a0|;
// over a step without a contact event, both rates while |j1 - j0| h <= kSingularRate times the
// larger acceleration (see BlockHermite::correct).
constexpr double kJerkTrust = 100;
constexpr double kSingularRate = 4;

// The corrector's a2, a3 that give the prediction the correction dv of its velocity and dx of
// its position at h: from a2 h^3/6 + a3 h^4/24 = dv and a2 h^4/24 + a3 h^5/120 = dx.
void correction_to_derivatives(const Vec3& dv, const Vec3& dx, double h, Vec3& a2, Vec3& a3) {
  const double h3 = h * h * h;
  const Vec3 a2h3 = (120.0 / h) * dx - 24.0 * dv;
  a2 = a2h3 / h3;
  a3 = (24.0 * dv - 4.0 * a2h3) / (h3 * h);
}

// The fits of a step over which the acceleration is not smooth (BlockHermite::correct), each
// as the a2, a3 of the corrector. Each leaves out what is not a derivative of the force over
// the step.
// a0, j0 and a1: a quadratic, for a rate at the step's end that is singular.
void fit_without_end_rate(const Vec3& a0, const Vec3& j0, const Vec3& a1, double h, Vec3& a2, Vec3& a3) {
  a2 = 2.0 * (a1 - a0 - h * j0) / (h * h);
  a3 = {};
}
// a0, a1 and j1: a(tau) = a0 + b tau + c tau^2, for a rate at the step's start that is
// singular. The predictor has already spent j0: the correction is the quadratic's less it,
// dv = (b - j0) h^2/2 + c h^3/3, dx = (b - j0) h^3/6 + c h^4/12.
void fit_without_start_rate(const Vec3& a0, const Vec3& j0, const Vec3& a1, const Vec3& j1, double h, Vec3& a2, Vec3& a3) {
  const double h2 = h * h, h3 = h2 * h;
  const Vec3 b = 2.0 * (a1 - a0) / h - j1, c = (h * j1 - (a1 - a0)) / h2;
  correction_to_derivatives((h2 / 2.0) * (b - j0) + (h3 / 3.0) * c, (h3 / 6.0) * (b - j0) + (h3 * h / 12.0) * c, h, a2, a3);
}
// A contact that began a time `since` before the step's end: the acceleration is a0 + j0 tau
// (what the prediction follows) plus, from the touch on, the new contact's A ((tau - t_touch) /
// since)^q, where A = a1 - a0 - j0 h is its part at the end and the power q in [0, 4] matches
// its rate there, j1 - j0 (q = 0: a force that sets in at once, as a linear dashpot; 3/2: Hertz;
// 1/4: Tsuji's dashpot). The correction is A since / (q + 1) in velocity and A since^2 /
// ((q + 1)(q + 2)) in position.
void fit_onset(const Vec3& a0, const Vec3& j0, const Vec3& a1, const Vec3& j1, double h, double since, Vec3& a2, Vec3& a3) {
  const Vec3 part = a1 - a0 - h * j0;
  const double size2 = norm2(part);
  const double q = size2 > 0 ? std::clamp(dot(j1 - j0, part) * since / size2, 0.0, 4.0) : 0.0;
  correction_to_derivatives((since / (q + 1)) * part, (since * since / ((q + 1) * (q + 2))) * part, h, a2, a3);
}
// A contact that ended a time `until` after the step's start, the mirror of fit_onset: the
// acceleration is a1 - j1 (h - tau) (the particle's without the contact, from the step's
// end) plus, until the release, the contact's C ((until - tau) / until)^q, where C = a0 -
// a1 + j1 h is its part at the start and q in [0, 4] matches its rate there, j0 - j1 (q = 0:
// a force that stops at once, as a linear dashpot's pull). The correction is that less what
// the prediction spent, a0 + j0 tau.
void fit_release(const Vec3& a0, const Vec3& j0, const Vec3& a1, const Vec3& j1, double h, double until, Vec3& a2, Vec3& a3) {
  const Vec3 part = a0 - a1 + h * j1;
  const double size2 = norm2(part);
  const double q = size2 > 0 ? std::clamp(-dot(j0 - j1, part) * until / size2, 0.0, 4.0) : 0.0;
  const double h2 = h * h;
  const Vec3 free_v = h * (a1 - h * j1 - a0) + (h2 / 2.0) * (j1 - j0), free_x = (h2 / 2.0) * (a1 - h * j1 - a0) + (h2 * h / 6.0) * (j1 - j0);
  const Vec3 dv = free_v + (until / (q + 1)) * part;
  const Vec3 dx = free_x + (h * until / (q + 1) - until * until / ((q + 1) * (q + 2))) * part;
  correction_to_derivatives(dv, dx, h, a2, a3);
}

// Aarseth's criterion from a, its first three derivatives at the step's end. |a| is taken
// no smaller than `a_floor` (gravity): a grain at terminal speed or at rest has a ~ 0, and
// the relative accuracy of a vanishing acceleration is not what limits its step.
double aarseth(double eta, double a_floor, const Vec3& a, const Vec3& j, const Vec3& a2, const Vec3& a3) {
  const double na = std::max(norm(a), a_floor), nj = norm(j), n2 = norm(a2), n3 = norm(a3);
  const double den = nj * n3 + n2 * n2;
  return den > 0 ? std::sqrt(eta * (na * n2 + nj * nj) / den) : kNever;
}

// The second-order estimate eta_s |a|/|j| (first steps, and after the force jumped), |a| no
// smaller than a_floor as in aarseth().
double second_order(double eta, double a_floor, const Vec3& a, const Vec3& j) {
  const double nj = norm(j);
  return nj > 0 ? eta * std::max(norm(a), a_floor) / nj : kNever;
}

// Union-find root with path halving.
std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double BlockHermite::tick(const World& world) const { return std::ldexp(world.dt, -rules_.levels); }

Predictor BlockHermite::predictor(const World& world, std::int64_t now) const {
  return Predictor{world.particles, world.domain, state_.time, state_.acc, state_.jerk, state_.alpha, state_.alpha_dot,
                   now, tick(world)};
}

Predictor BlockHermite::predictor_cached(const World& world, std::int64_t now) const {
  Predictor kin = predictor(world, now);
  kin.cached = predicted_.data(), kin.cached_at = predicted_at_.data();
  return kin;
}

void BlockHermite::predict_around(const World& world, std::int64_t t, std::size_t from) {
  const std::size_t n = world.particles.size();
  predicted_.resize(n);
  predicted_at_.resize(n, -1);
  to_predict_.clear();
  auto claim = [&](std::uint32_t i) {
    if (predicted_at_[i] != t) predicted_at_[i] = t, to_predict_.push_back(i);
  };
  for (std::size_t q = from; q < active_.size(); ++q) {
    claim(active_[q]);
    world.contacts.for_each_pair_of(active_[q], [&](std::uint32_t j, std::uint32_t) { claim(j); });
  }
  const Predictor kin = predictor(world, t);  // not the cached one: its entries are claimed, not yet made
  parallel_for(to_predict_.size(), [&](std::size_t q) { predicted_[to_predict_[q]] = kin.at(to_predict_[q]); });
}

int level_needed(double dt, double bound) {
  if (bound >= dt) return 0;
  const double k = std::ceil(std::log2(dt / bound));
  return k < kBeyondLevels ? static_cast<int>(k) : kBeyondLevels;  // a NaN compares false
}

int BlockHermite::level_for(double bound, const World& world) const {
  if (rules_.force_level >= 0) return rules_.force_level;
  return std::min(level_needed(world.dt, bound), rules_.levels);
}

void BlockHermite::set_level(std::uint32_t i, int level) {
  const int old = state_.level[i];
  if (old == level && slot_[i] != UINT32_MAX) return;
  if (slot_[i] != UINT32_MAX) {  // out of the old level's list (swap with its last)
    auto& from = members_[static_cast<std::size_t>(old)];
    const std::uint32_t moved = from.back();
    from[slot_[i]] = moved;
    slot_[moved] = slot_[i];
    from.pop_back();
  }
  auto& to = members_[static_cast<std::size_t>(level)];
  slot_[i] = static_cast<std::uint32_t>(to.size());
  to.push_back(i);
  state_.level[i] = static_cast<std::uint8_t>(level);
}

void BlockHermite::index_levels() {
  members_.assign(static_cast<std::size_t>(rules_.levels) + 1, {});
  slot_.assign(state_.size(), UINT32_MAX);
  for (std::uint32_t i = 0; i < state_.size(); ++i) set_level(i, state_.level[i]);
}

void BlockHermite::size_scratch(std::size_t n) {
  rates_.resize(n);
  for (auto* v : {&change_v_, &change_w_, &change_f_, &change_t_}) v->resize(n);
  aarseth_.resize(n, kNever);
  measured_rate_.resize(n, kNever);
}

void BlockHermite::start(World& world, ForceField& forces) {
  const std::size_t n = world.particles.size();
  const std::int64_t now = world.step << rules_.levels;
  state_ = {};
  state_.resize(n);
  std::fill(state_.time.begin(), state_.time.end(), now);
  index_levels();
  size_scratch(n);
  measured_rate_.assign(n, kNever);  // no correction yet
  is_active_.assign(n, 1);
  active_.resize(n);
  std::iota(active_.begin(), active_.end(), 0u);
  walls_at(world, now);
  rebuild_lists(world, forces, now);
  // Twice: the first gives the accelerations that the rates of damping and drag need.
  std::vector<int> contacts_before(world.particles.contact_count);
  for (int pass = 0; pass < 2; ++pass) {
    forces.compute_active(world, predictor(world, now), active_, is_active_,
                          contact_rules(), rates_);
    parallel_for(n, [&](std::size_t i) { take_state(world, forces, i); });
  }
  stats_.evaluations[0] += n;  // the first evaluation, counted once
  std::fill(contacts_before.begin(), contacts_before.end(), -1);  // every step is a first step
  fluid_slope_.assign(n, FluidSlope{});  // no corrector ran: the relaxation times from the law
  choose_levels(world, forces, now, contacts_before);
  std::fill(is_active_.begin(), is_active_.end(), 0);
  active_.clear();
}

void BlockHermite::take_state(World& world, const ForceField& forces, std::size_t i) {
  // p.force/torque and rates_ hold gravity and the contacts at the particle's own time; the
  // fluid's forces are added here (at the current velocity and spin, the rates along the
  // accelerations they give).
  Particles& p = world.particles;
  const double d = 2 * p.radius[i], m = p.translational_mass[i];
  const Crowding& crowd = forces.crowding(i);
  const FluidLoad fl = fluid_load(forces.model().fluid, d, forces.model().gravity, p.velocity[i], p.omega[i], crowd);
  state_.acc[i] = (p.force[i] + fl.force) / m;
  state_.alpha[i] = (p.torque[i] + fl.torque) / p.inertia[i];
  const FluidLoad fr = fluid_load_rate(forces.model().fluid, d, p.velocity[i], state_.acc[i], p.omega[i], state_.alpha[i], crowd);
  state_.jerk[i] = (rates_.force[i] + fr.force) / m;
  state_.alpha_dot[i] = (rates_.torque[i] + fr.torque) / p.inertia[i];
  p.force[i] += fl.force, p.torque[i] += fl.torque;
}

void BlockHermite::particles_added(World& world, ForceField& forces, std::size_t first) {
  // The new particles are evaluated at once, after the lists are rebuilt with them, so that
  // their first steps follow the gap rule too: two grains entering close together, each on
  // a free grain's long step, once began a contact inside both steps (117 % overlap). An
  // older neighbour on a longer step is then woken by the new one's gap (see wake()).
  Particles& p = world.particles;
  const std::size_t n = p.size();
  const std::int64_t now = world.step << rules_.levels;
  state_.resize(n);
  size_scratch(n);
  is_active_.resize(n, 0);
  slot_.resize(n, UINT32_MAX);
  std::vector<std::uint32_t> fresh;
  forces.admit_new_particles(p);
  for (std::size_t i = first; i < n; ++i) {
    state_.time[i] = now;
    fresh.push_back(static_cast<std::uint32_t>(i));
    is_active_[i] = 1;
  }
  walls_at(world, now);
  rebuild_lists(world, forces, now);
  forces.compute_active(world, predictor(world, now), fresh, is_active_,
                        contact_rules(), rates_);
  for (std::uint32_t i : fresh) {
    take_state(world, forces, i);
    const double bound = std::min({rates_.step_bound[i], dashpot_step(i, false), second_order(rules_.eta_s, norm(forces.model().gravity), state_.acc[i], state_.jerk[i]),
                                   rules_.eta_tau * drag_relaxation_time(forces.model().fluid, 2 * p.radius[i], p.translational_mass[i],
                                                                         norm(p.velocity[i]), forces.crowding(i)),
                                   until_wall_event(world, i, now)});
    set_level(i, level_for(bound, world));
    ++stats_.evaluations[state_.level[i]];
    is_active_[i] = 0;
  }
}

void BlockHermite::resume(World& world, ForceField& forces, HermiteState state, std::vector<Vec3> list_positions,
                          std::vector<double> list_reach, bool lists_stale, const BlockStepStats& stats) {
  const std::size_t n = world.particles.size();
  state_ = std::move(state);
  stats_ = stats;
  stats_.evaluations.resize(static_cast<std::size_t>(rules_.levels) + 1, 0);
  size_scratch(n);
  is_active_.assign(n, 0);
  active_.clear();
  index_levels();
  list_positions_ = std::move(list_positions);
  list_reach_ = std::move(list_reach);
  build_lists(world, forces);  // the lists the run had
  lists_stale_ = lists_stale;
}

void BlockHermite::build_lists(World& world, ForceField& forces) {
  forces.rebuild_at(world, list_positions_, list_reach_, wall_reach(world));
  list_skin_ = forces.skin();
}

void BlockHermite::rebuild_lists(World& world, ForceField& forces, std::int64_t t) {
  const Particles& p = world.particles;
  const std::size_t n = p.size();
  const Predictor kin = predictor(world, t);
  const double horizon = rules_.list_horizon * world.dt;
  const double skin = forces.skin_of(world);
  list_positions_.resize(n);
  list_reach_.resize(n);
  parallel_for(n, [&](std::size_t i) {
    const Kinematics k = kin.at(i);
    list_positions_[i] = k.x;
    // How far the grain can go in the horizon, at least a skin (grains creeping in a
    // deposit would otherwise ask for a new list each time one of them has moved half a
    // skin), at most one own diameter: a falling grain keeps its list for several dt.
    list_reach_[i] = std::clamp(norm(k.v) * horizon + 0.5 * norm(k.a) * horizon * horizon, skin, 2 * p.radius[i]);
  });
  build_lists(world, forces);
  lists_stale_ = false;
}

std::vector<double> BlockHermite::wall_reach(const World& world) const {
  // How far a wall can travel in the list horizon: a grain it could reach before the lists
  // are next checked is listed, so that its gap rule sees the wall coming.
  // A turning mesh's surface moves at up to its angular velocity times its farthest vertex's
  // distance from the axis besides.
  std::vector<double> reach;
  for (const Wall& w : world.walls)
    reach.push_back((w.top_speed() + w.top_turning_rate() * turning_reach(w)) * rules_.list_horizon * world.dt);
  return reach;
}

void BlockHermite::walls_at(World& world, std::int64_t t) const {
  // The velocity and surface motion of the stretches that begin at or hold t: those the
  // walls keep over the steps that start at t (no step straddles a change, see
  // until_wall_event), which the contacts' forces and gap rules at t take. (A turning mesh's
  // angle is its closed form at t, Wall::turn_to.)
  const double now = static_cast<double>(t) * tick(world);
  for (Wall& w : world.walls) w.motion_during(now);
}

double BlockHermite::until_wall_event(const World& world, std::uint32_t i, std::int64_t t) const {
  // A change of a listed wall's motion or of its surface's motion ends the particle's step: a
  // step chosen while the floor stood still, and straddling the moment it starts to rise, met
  // the floor inside the step (a grain 7.8 um above it flung off at 11 m/s).
  const double now = static_cast<double>(t) * tick(world);
  double until = kNever;
  world.contacts.for_each_wall_of(i, [&](std::uint32_t element, std::uint32_t) {
    until = std::min(until, world.walls[world.wall_of(element)].next_change(now) - now);
  });
  return until;
}

double BlockHermite::list_limit(std::uint32_t i) const {
  return list_reach_[i] + 0.45 * list_skin_;  // 10 % of the half skin spare for the corrector
}

double BlockHermite::moved_since_list(const World& world, std::uint32_t i, const Vec3& x) const {
  return norm(world.domain.separation(x, list_positions_[i]));
}

bool BlockHermite::list_outrun(const World& world, const Predictor& kin, std::uint32_t i) const {
  // Where the particle, about to be evaluated at the predictor's time, can be by the end of
  // its next step (at most twice its current one; the Taylor series' terms bounded one by
  // one), against where the list allows it to go: the gap rules of that step need every
  // neighbour it could reach listed.
  const Kinematics k = kin.at(i);
  const int next_level = std::max(int(state_.level[i]) - 1, 0);
  const double s = static_cast<double>(step_ticks(next_level)) * tick(world);
  const double moved = moved_since_list(world, i, k.x);
  const double ahead = s * (norm(k.v) + s * (0.5 * norm(k.a) + s / 6.0 * norm(state_.jerk[i])));
  return moved + ahead > list_limit(i);
}

int BlockHermite::coarsest_on_grid(std::int64_t t) const {
  // Level k's steps end at multiples of 2^(L-k) ticks: L less the trailing zeros of t.
  const int zeros = t == 0 ? rules_.levels : std::min(std::countr_zero(static_cast<std::uint64_t>(t)), rules_.levels);
  return rules_.levels - zeros;
}

void BlockHermite::collect_active(std::int64_t t) {
  active_.clear();
  for (int k = coarsest_on_grid(t); k <= rules_.levels; ++k)  // the levels whose steps end at t
    for (std::uint32_t i : members_[static_cast<std::size_t>(k)]) active_.push_back(i);
  std::sort(active_.begin(), active_.end());  // the same order whatever the level history
  for (std::uint32_t i : active_) is_active_[i] = 1;
}

void BlockHermite::wake(const World& world, std::int64_t t) {
  // Two reasons to evaluate an inactive listed neighbour j of an active particle i at t,
  // with shared levels with every particle j touches (they share its time: a contact is
  // never evaluated from one side only). Its step then ends at t, not at a power of two: the
  // corrector takes any h.
  // - j would touch i at t and did not at the contact's last evaluation: its new contact
  //   woke it (is_active 2, see correct()). With a level spread s > 0 a contact that
  //   already touched wakes j only if j's level is more than s coarser than i's: else j,
  //   on a longer step, takes the contact's force at its own step ends, the contact
  //   evaluated at the ends of either grain's steps with the other predicted there.
  // - j's step is longer than i's and would end after their gap closes: j chose that step
  //   before i came near (i may have entered j's list since, or sped up), so its gap rule
  //   never saw i. Evaluated now, it picks a step from the gap; without this, the contact
  //   began inside j's long step, whose corrector spread the new force over the whole step
  //   (a 1 mm grain on a 0.5 ms step flung off at 3.5 m/s, the pair then 109 % overlapped).
  const Predictor kin = predictor_cached(world, t);
  const Particles& p = world.particles;
  const ContactList& contacts = world.contacts;
  const double dt_tick = tick(world);
  std::vector<std::uint32_t> stack;
  for (std::size_t q = 0; q < active_.size(); ++q) {
    const std::uint32_t i = active_[q];
    const Kinematics ki = kin.at(i);
    contacts.for_each_pair_of(i, [&](std::uint32_t j, std::uint32_t k) {
      if (is_active_[j]) return;
      if (rules_.level_spread > 0 && contacts.pairs()[k].touching && state_.level[j] + rules_.level_spread >= state_.level[i]) return;
      const Kinematics kj = kin.at(j);
      const Vec3 d = world.domain.separation(ki.x, kj.x);
      const double reach = p.radius[i] + p.radius[j];
      char why = 0;
      if (norm2(d) < reach * reach) {  // the evaluation's touching test
        why = 2;
      } else if (state_.level[j] < state_.level[i]) {
        const double dist = norm(d);
        const Vec3 n = d / dist;
        const double closes = time_to_close(dist - reach, -dot(ki.v - kj.v, n), -dot(ki.a - kj.a, n));
        const std::int64_t ends = state_.time[j] + step_ticks(state_.level[j]);
        if (static_cast<double>(ends - t) * dt_tick > closes) why = 1;
      }
      if (!why) return;
      stack.push_back(j);
      while (!stack.empty()) {
        const std::uint32_t w = stack.back();
        stack.pop_back();
        if (is_active_[w]) continue;
        is_active_[w] = w == j ? why : 1;
        active_.push_back(w);
        ++stats_.wakes;
        if (rules_.level_spread == 0)  // else each woken grain's partners are checked in turn
          contacts.for_each_pair_of(w, [&](std::uint32_t y, std::uint32_t c) {
            if (!is_active_[y] && contacts.pairs()[c].touching) stack.push_back(y);
          });
      }
    });
  }
}

std::pair<std::size_t, std::size_t> BlockHermite::share_of(int rank) const {
  const std::size_t n = active_.size(), processes = share_ ? static_cast<std::size_t>(share_->size()) : 1;
  const auto r = static_cast<std::size_t>(rank);
  return {n * r / processes, n * (r + 1) / processes};
}

void BlockHermite::take_share() { std::tie(share_begin_, share_end_) = share_of(share_ ? share_->rank() : 0); }

template <class Each>
void BlockHermite::rates_of(std::uint32_t i, Each&& each) {
  each(rates_.force[i]), each(rates_.torque[i]), each(rates_.step_bound[i]), each(rates_.damping_rate[i]);
  each(rates_.touched_for[i]), each(rates_.released_for[i]);
}

template <class Each>
void BlockHermite::corrected(World& world, std::size_t q, Each&& each) {
  Particles& p = world.particles;
  const std::uint32_t i = active_[q];
  each(p.position[i]), each(p.velocity[i]), each(p.omega[i]), each(p.force[i]), each(p.torque[i]);
  each(state_.acc[i]), each(state_.jerk[i]), each(state_.alpha[i]), each(state_.alpha_dot[i]), each(state_.time[i]);
  each(aarseth_[i]), each(change_v_[i]), each(change_w_[i]);
  each(predicted_acc_[q]), each(predicted_alpha_[q]), each(fluid_slope_[q]);
}

void BlockHermite::evaluate(World& world, ForceField& forces, std::int64_t t) {
  take_share();
  const Predictor kin = predictor_cached(world, t);
  if (!share_) return forces.compute_active(world, kin, active_, is_active_, contact_rules(), rates_);
  const std::span<const std::uint32_t> mine(active_.data() + share_begin_, share_end_ - share_begin_);
  here_.resize(world.particles.size(), 0);
  for (std::uint32_t i : mine) here_[i] = 1;
  const double worst = forces.evaluate_active(world, kin, mine, is_active_, here_, contact_rules(), rates_);
  for (std::uint32_t i : mine) here_[i] = 0;
  // What this process found, for the others (exchange_share).
  shared_bytes_.clear();
  put(shared_bytes_, worst);
  forces.pack_active(world, mine, is_active_, shared_bytes_);
  for (std::uint32_t i : mine) rates_of(i, [&](const auto& v) { put(shared_bytes_, v); });
}

void BlockHermite::exchange_share(World& world, ForceField& forces) {
  for (std::size_t q = share_begin_; q < share_end_; ++q) corrected(world, q, [&](const auto& v) { put(shared_bytes_, v); });
  const std::vector<std::string_view> all = share_->gather_all(shared_bytes_);
  double deepest = 0;
  std::vector<std::size_t> corrections(all.size());  // where each process's corrected state begins
  for (int r = 0; r < share_->size(); ++r) {
    const std::string_view b = all[static_cast<std::size_t>(r)];
    std::size_t at = 0;
    const auto w = take<double>(b, at);
    if (!(w <= deepest)) deepest = w;  // a NaN too
    if (r == share_->rank()) continue;
    forces.take_active(world, b, at);
    const auto [begin, end] = share_of(r);
    for (std::size_t q = begin; q < end; ++q) rates_of(active_[q], [&](auto& v) { v = take<std::decay_t<decltype(v)>>(b, at); });
    corrections[static_cast<std::size_t>(r)] = at;
  }
  if (!(deepest <= forces.model().overlap_limit)) {  // the step ends at the evaluation, as for one process
    std::size_t at = 0;
    for (std::size_t q = share_begin_; q < share_end_; ++q)
      corrected(world, q, [&](auto& v) { v = take<std::decay_t<decltype(v)>>(uncorrected_, at); });
    forces.check_overlaps(world, deepest);
  }
  for (int r = 0; r < share_->size(); ++r) {
    if (r == share_->rank()) continue;
    const std::string_view b = all[static_cast<std::size_t>(r)];
    std::size_t at = corrections[static_cast<std::size_t>(r)];
    const auto [begin, end] = share_of(r);
    for (std::size_t q = begin; q < end; ++q) corrected(world, q, [&](auto& v) { v = take<std::decay_t<decltype(v)>>(b, at); });
  }
}

void BlockHermite::correct(World& world, ForceField& forces, std::int64_t t, const std::vector<int>& contacts_before) {
  // Spec section 1, corrector: with h = t - t_i,
  //   a2 = (-6 (a0 - a1) - h (4 j0 + 2 j1)) / h^2, a3 = (12 (a0 - a1) + 6 h (j0 + j1)) / h^3,
  //   x = x_p + a2 h^4/24 + a3 h^5/120, v = v_p + a2 h^3/6 + a3 h^4/24; rotation likewise.
  // Over a step in which a contact began or ended the force is not smooth, and j0 or j1 may
  // be no derivative of it over the step: Tsuji's dashpot (eta ~ delta^1/4) has a rate
  // ~ delta^-3/4, unbounded at first touch and at release, and a linear dashpot's force sets
  // in at once. The corrector then fits what it knows of the force (the fits above):
  // - a contact began: the onset is located in the step (EvaluationRates::touched_for) and
  //   the new contact's force fitted from it on (fit_onset); spreading it over the whole
  //   step instead erred to first order in the step (Chung & Ooi test 3 at the default rules
  //   and dt = 5 us: a linear contact with e = 0.3 rebounded with e up to 4.9 % off). When
  //   the onset is not known (two contacts began), and j1 changed far more than the
  //   accelerations allow (|j1 - j0| h > kJerkTrust |a1 - a0|), a0, j0 and a1.
  // - a contact ended, and j1 changed far more than that: a0, a1 and j1, since j0 was the
  //   singular one (a bouncing grain otherwise left 10 % too fast).
  // - no contact event, but a rate far beyond what the accelerations allow for a smooth force
  //   over the step (|j1 - j0| h > kSingularRate max(|a0|, |a1|, g): resolved smooth forces
  //   give (omega h)^2 << 1): the larger rate is left out. A Tsuji contact about to open
  //   (delta = 3e-8 m at the step's end) gave j1 ~ 3e13 m/s^3, and the rebound of a grain
  //   with e = 0.1 came out at 0.04.
  // j1 is kept for the next step, which the second-order rule after a contact event makes short.
  Particles& p = world.particles;
  const Predictor kin = predictor_cached(world, t);
  const double dt_tick = tick(world);
  predicted_acc_.resize(active_.size()), predicted_alpha_.resize(active_.size()), fluid_slope_.resize(active_.size());
  if (share_) {  // this share's state before the corrector, should an overlap elsewhere end the step here
    uncorrected_.clear();
    for (std::size_t q = share_begin_; q < share_end_; ++q) corrected(world, q, [&](const auto& v) { put(uncorrected_, v); });
  }
  parallel_for(share_end_ - share_begin_, [&](std::size_t s) {  // this process's share
    const std::size_t q = share_begin_ + s;
    const std::uint32_t i = active_[q];
    const double h = static_cast<double>(t - state_.time[i]) * dt_tick;
    const Kinematics pred = kin.at(i);
    predicted_acc_[q] = pred.a, predicted_alpha_[q] = pred.alpha;
    const double m = p.translational_mass[i], inertia = p.inertia[i];
    const double h2 = h * h, h3 = h2 * h, h4 = h3 * h;
    const bool began = contacts_before[q] < p.contact_count[i], ended = contacts_before[q] > p.contact_count[i];
    const double since = std::min(rates_.touched_for[i], h);  // 0: the onset is not known
    const double released = std::min(rates_.released_for[i], h);  // 0: the release is not known
    const double g = norm(forces.model().gravity);
    auto corrector = [&](const Vec3& a0, const Vec3& j0, const Vec3& a1, const Vec3& j1, Vec3& a2, Vec3& a3) {
      const double jump = norm(j1 - j0) * h;
      if (began && since > 0) return fit_onset(a0, j0, a1, j1, h, since, a2, a3);
      if (ended && released > 0) return fit_release(a0, j0, a1, j1, h, h - released, a2, a3);
      if ((began || ended) && jump > kJerkTrust * norm(a1 - a0))
        return began ? fit_without_end_rate(a0, j0, a1, h, a2, a3) : fit_without_start_rate(a0, j0, a1, j1, h, a2, a3);
      if (!began && !ended && jump > kSingularRate * std::max({norm(a0), norm(a1), g}))
        return norm(j1) >= norm(j0) ? fit_without_end_rate(a0, j0, a1, h, a2, a3) : fit_without_start_rate(a0, j0, a1, j1, h, a2, a3);
      a2 = (-6.0 * (a0 - a1) - h * (4.0 * j0 + 2.0 * j1)) / (h * h);
      a3 = (12.0 * (a0 - a1) + 6.0 * h * (j0 + j1)) / (h * h * h);
    };
    // Contacts and gravity from the evaluation; the still fluid's velocity-dependent forces
    // taken twice, at the predicted and then at the corrected velocity and spin (P(EC)^2 for
    // the fluid), with rates from the evaluated accelerations: fourth order where the fluid
    // alone acts (docs/integrators.md). Without lift the second pass moves the first along
    // the load's slope (FluidSlope: the velocity changes by O(h^3), the slope's error is
    // O(h^6)); a lift model is evaluated again.
    const Vec3 f_c = p.force[i], t_c = p.torque[i];
    // A woken particle's contact began near the end of its step, after a free flight that its
    // prediction follows to fourth order: the onset located, it is corrected from there
    // like its partner; else it keeps the prediction (the corrector would spread the new
    // contact force over the whole step) and starts its next step with the new force.
    const bool woken = is_active_[i] == 2 && !(began && since > 0);
    Vec3 v = pred.v, w = pred.w, a1 = pred.a, al1 = pred.alpha, j1, ad1, a2, a3, b2, b3;
    const Fluid& fluid_model = forces.model().fluid;
    const int passes = fluid_model.enabled ? 2 : 1;
    FluidSlope& slope = fluid_slope_[q];
    FluidLoadWithRate fluid;
    for (int pass = 0; pass < passes; ++pass) {
      // The rates are taken along the accelerations of the pass before (the predicted ones
      // first): the second pass's are within O(h^3) of the true ones.
      if (pass == 0 || !slope.exact) {
        fluid = fluid_load_with_rate(fluid_model, 2 * p.radius[i], forces.model().gravity, v, a1, w, al1, forces.crowding(i), &slope);
      } else {
        fluid.value.force += slope.force_change(v - pred.v), fluid.value.torque += slope.torque_change(w - pred.w);
        fluid.rate.force += slope.force_change(a1 - pred.a), fluid.rate.torque += slope.torque_change(al1 - pred.alpha);
      }
      const FluidLoad &fl = fluid.value, &fr = fluid.rate;
      a1 = (f_c + fl.force) / m, al1 = (t_c + fl.torque) / inertia;
      j1 = (rates_.force[i] + fr.force) / m, ad1 = (rates_.torque[i] + fr.torque) / inertia;
      corrector(state_.acc[i], state_.jerk[i], a1, j1, a2, a3);
      corrector(state_.alpha[i], state_.alpha_dot[i], al1, ad1, b2, b3);
      v = pred.v + (h3 / 6.0) * a2 + (h4 / 24.0) * a3;
      w = pred.w + (h3 / 6.0) * b2 + (h4 / 24.0) * b3;
      if (pass + 1 == passes) p.force[i] = f_c + fl.force, p.torque[i] = t_c + fl.torque;
    }
    const Vec3 x = woken ? pred.x : world.domain.wrap(pred.x + (h4 / 24.0) * a2 + (h4 * h / 120.0) * a3);
    p.position[i] = x;
    p.velocity[i] = woken ? pred.v : v;
    p.omega[i] = woken ? pred.w : w;
    change_v_[i] = p.velocity[i] - pred.v, change_w_[i] = p.omega[i] - pred.w;
    state_.acc[i] = a1, state_.jerk[i] = j1, state_.alpha[i] = al1, state_.alpha_dot[i] = ad1;
    state_.time[i] = t;
    // Aarseth's criterion with the derivatives at the step's end, for free particles (spec section 2); a particle in touch takes
    // the contact rules, which follow its contacts' stiffness. Not after a step whose last
    // contact ended: the fit's a2, a3 are no derivatives of a smooth force (without gravity
    // to floor |a| they asked for the finest level), and the event rule takes over there.
    aarseth_[i] = !woken && p.contact_count[i] == 0 && !ended ? aarseth(rules_.eta_a, g, a1, j1, a2 + h * a3, a3) : kNever;
  });
  if (share_) exchange_share(world, forces);
  for (std::uint32_t i : active_) ++stats_.evaluations[state_.level[i]];  // evaluated, the overlaps checked
  for (std::uint32_t i : active_) {
    const Vec3 x = p.position[i];
    if (!(world.domain.kept(x) && std::isfinite(x.x + x.y + x.z))) {  // beyond an open face: removed at the step's end
      const Vec3 v = p.velocity[i];
      std::ostringstream msg;
      msg << "step " << world.step + 1 << " (block time " << world.time << " s, level " << int(state_.level[i])
          << "): particle id " << p.id[i] << " left the domain or is not finite: x = (" << x.x << ", " << x.y << ", "
          << x.z << ") m, v = (" << v.x << ", " << v.y << ", " << v.z << ") m/s; a wall may be missing, or the step"
          << " rules too loose for this problem ([simulation.block_steps])";
      throw NumericalError(msg.str());
    }
  }
  correct_dashpots(world, forces);
}

void BlockHermite::correct_dashpots(World& world, const ForceField& forces) {
  // The contacts were evaluated at the predicted velocities: the dashpots' forces, linear in
  // the velocities, are brought to the corrected ones, and their rates to the corrected
  // accelerations (in effect a second evaluation of the dashpots, the only velocity-
  // dependent contact forces). Without it the scheme is stable for a dashpot's decay rate
  // lambda only while lambda h < 0.61; with it while lambda h < 2.5 (docs/integrators.md).
  Particles& p = world.particles;
  forces.dashpot_response(world, active_, change_v_, change_w_, change_f_, change_t_);
  const bool measure = rules_.damping_rate == DampingRate::measured;
  for (std::size_t q = 0; q < active_.size(); ++q) {
    const std::uint32_t i = active_[q];
    // The dashpots' decay rate along this correction: the response to the change of velocity
    // and spin over that change, |M^-1/2 dF| / |M^1/2 dv|, a Rayleigh quotient of the damping
    // operator. It never exceeds the operator's largest rate, and once a mode the step
    // leaves unstable grows, the change is that mode and the quotient its rate (stiffness
    // detection along the solution, Shampine 1977). Unknown where nothing changed (a woken
    // grain keeps its prediction).
    const double m = p.translational_mass[i], inertia = p.inertia[i];
    if (measure) {
      const double moved = m * norm2(change_v_[i]) + inertia * norm2(change_w_[i]);
      const double pushed = norm2(change_f_[i]) / m + norm2(change_t_[i]) / inertia;
      measured_rate_[i] = moved > 0 ? std::sqrt(pushed / moved) : kNever;
    }
    p.force[i] += change_f_[i], p.torque[i] += change_t_[i];
    state_.acc[i] += change_f_[i] / m;
    state_.alpha[i] += change_t_[i] / inertia;
    change_v_[i] = state_.acc[i] - predicted_acc_[q], change_w_[i] = state_.alpha[i] - predicted_alpha_[q];
  }
  forces.dashpot_response(world, active_, change_v_, change_w_, change_f_, change_t_);
  for (std::uint32_t i : active_) {
    state_.jerk[i] += change_f_[i] / p.translational_mass[i];
    state_.alpha_dot[i] += change_t_[i] / p.inertia[i];
    change_v_[i] = {}, change_w_[i] = {};
  }
}

double BlockHermite::dashpot_step(std::uint32_t i, bool measured) const {
  const double rate = measured ? std::min(rates_.damping_rate[i], measured_rate_[i]) : rates_.damping_rate[i];
  return rate > 0 ? rules_.eta_damping / rate : kNever;
}

void BlockHermite::choose_levels(const World& world, const ForceField& forces, std::int64_t t,
                                 const std::vector<int>& contacts_before) {
  const Particles& p = world.particles;
  // Each active particle's wish: contacts and gaps (from the evaluation), the fluid's
  // relaxation time, Aarseth (from the corrector) or, after a contact began or ended, the
  // second-order estimate.
  std::vector<int> wish(active_.size());
  std::vector<StepRule> reason(active_.size());  // the rule that set each wish
  parallel_for(active_.size(), [&](std::size_t q) {
    const std::uint32_t i = active_[q];
    double bound = rates_.step_bound[i];
    StepRule& why = reason[q];
    why = StepRule::contact_or_gap;
    const auto take = [&](double b, StepRule rule) {
      if (b < bound) bound = b, why = rule;
    };
    take(dashpot_step(i, rules_.damping_rate == DampingRate::measured), StepRule::dashpot);
    take(aarseth_[i], StepRule::aarseth);
    // The drag's relaxation time from the corrector's slope (the same law, without a pow).
    const FluidSlope& slope = fluid_slope_[q];
    const double relaxation = slope.exact ? slope.relaxation_time(p.translational_mass[i], norm(p.velocity[i]))
                                          : drag_relaxation_time(forces.model().fluid, 2 * p.radius[i], p.translational_mass[i],
                                                                 norm(p.velocity[i]), forces.crowding(i));
    take(rules_.eta_tau * relaxation, StepRule::fluid);
    // The gap rules know only the listed neighbours: a step must not carry the particle out
    // of the region its list covers (a fast grain on a long step would pass through grains it
    // has not listed yet).
    const double room = list_limit(i) - moved_since_list(world, i, p.position[i]);
    take(time_to_close(std::max(room, 0.0), norm(p.velocity[i]), norm(state_.acc[i])), StepRule::list);
    take(until_wall_event(world, i, t), StepRule::wall_motion);
    // The second-order estimate after a grain's first touch from free flight (a force whose
    // rate is singular at the onset, as Tsuji's dashpot, needs short steps there) and after
    // its last contact ended (Aarseth's criterion restarts). Not when a grain already in
    // touch gains or loses one contact: model H's dashpot makes |j| ~ |a| eta/m there, and
    // eta_s |a|/|j| ~ eta_s m/eta (35 ns for 0.5 mm grains) would hold the grain, and
    // through the level spread its partners, on it while any of its contacts opens or closes.
    if (contacts_before[q] != p.contact_count[i] && (contacts_before[q] == 0 || p.contact_count[i] == 0))
      take(second_order(rules_.eta_s, norm(forces.model().gravity), state_.acc[i], state_.jerk[i]), StepRule::event);
    int level = level_for(bound, world);
    if (rules_.force_level < 0) {
      const int own = level;
      level = std::max(level, int(state_.level[i]) - 1);  // double at most once a step
      level = std::max(level, coarsest_on_grid(t));  // the new step must start on its own grid
      if (level != own) why = StepRule::doubling;
    }
    wish[q] = level;
  });
  std::vector<std::uint32_t>& where = place_in_active_;  // UINT32_MAX outside the active set
  where.resize(p.size(), UINT32_MAX);
  for (std::uint32_t q = 0; q < active_.size(); ++q) where[active_[q]] = q;
  if (rules_.level_spread > 0) return spread_levels(world, wish, reason);
  // Particles in touch share the finest wish of their cluster (level_spread 0).
  std::vector<std::uint32_t> parent(active_.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::uint32_t q = 0; q < active_.size(); ++q)
    world.contacts.for_each_pair_of(active_[q], [&](std::uint32_t j, std::uint32_t k) {
      if (world.contacts.pairs()[k].touching && where[j] != UINT32_MAX) {
        const std::uint32_t a = root(parent, q), b = root(parent, where[j]);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    });
  std::vector<int> cluster(active_.size(), -1);
  // The member whose wish the cluster takes, whose rule the statistics credit: of those with
  // the finest wish, the one with the smallest id (whatever the particles' numbering).
  std::vector<std::uint32_t> finest(active_.size());
  for (std::uint32_t q = 0; q < active_.size(); ++q) {
    const std::uint32_t r = root(parent, q);
    if (wish[q] > cluster[r] || (wish[q] == cluster[r] && p.id[active_[q]] < p.id[active_[finest[r]]]))
      cluster[r] = wish[q], finest[r] = q;
  }
  for (std::uint32_t q = 0; q < active_.size(); ++q) {
    const std::uint32_t r = root(parent, q);
    if (wish[q] == cluster[r]) ++stats_.set_by_own[static_cast<std::size_t>(reason[q])];
    else ++stats_.set_by_cluster[static_cast<std::size_t>(reason[finest[r]])];
    set_level(active_[q], cluster[r]);
  }
  for (std::uint32_t i : active_) where[i] = UINT32_MAX;
}

void BlockHermite::spread_levels(const World& world, std::vector<int>& wish, const std::vector<StepRule>& reason) {
  // Grains in touch within level_spread levels of each other: each active grain's level is
  // the finest of its own wish and its active partners' levels less the spread, the least
  // such levels (one fixed point whatever the order of the passes). An inactive partner is
  // never finer than an active grain (its step would have ended first); one too coarse was
  // woken (wake()). A grain whose level a partner set counts it under that partner's rule.
  std::vector<std::uint32_t>& where = place_in_active_;
  std::vector<std::uint32_t> set_by(active_.size());
  std::iota(set_by.begin(), set_by.end(), 0u);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::uint32_t q = 0; q < active_.size(); ++q)
      world.contacts.for_each_pair_of(active_[q], [&](std::uint32_t j, std::uint32_t k) {
        const std::uint32_t r = where[j];
        // Each pair is met from both grains: q is raised from r here, r from q there.
        if (r == UINT32_MAX || !world.contacts.pairs()[k].touching || wish[r] - rules_.level_spread <= wish[q]) return;
        wish[q] = wish[r] - rules_.level_spread, set_by[q] = set_by[r], changed = true;
      });
  }
  for (std::uint32_t q = 0; q < active_.size(); ++q) {
    if (set_by[q] == q) ++stats_.set_by_own[static_cast<std::size_t>(reason[q])];
    else ++stats_.set_by_cluster[static_cast<std::size_t>(reason[set_by[q]])];
    set_level(active_[q], wish[q]);
  }
  for (std::uint32_t i : active_) where[i] = UINT32_MAX;
}

void BlockHermite::renumber(const std::vector<std::uint32_t>& order) {
  state_.for_each_array([&](auto& a) {
    permute(a, order);
    a.resize(order.size());  // shorter when grains have left
  });
  size_scratch(order.size());
  is_active_.assign(order.size(), 0);
  predicted_at_.assign(order.size(), -1);
  index_levels();
  lists_stale_ = true;
}

void BlockHermite::particles_removed(World& world, ForceField& forces, const std::vector<std::uint32_t>& kept) {
  renumber(kept);
  rebuild_lists(world, forces, world.step << rules_.levels);
}

void BlockHermite::advance(World& world, ForceField& forces) {
  const std::int64_t begin = world.step << rules_.levels, end = begin + (std::int64_t{1} << rules_.levels);
  const double dt_tick = tick(world);
  std::int64_t now = begin;
  std::vector<int> contacts_before;
  while (now < end) {
    int finest = 0;
    for (int k = rules_.levels; k >= 0; --k)
      if (!members_[static_cast<std::size_t>(k)].empty()) { finest = k; break; }
    const std::int64_t h = step_ticks(finest);
    const std::int64_t t = now - now % h + h;
    for (Wall& w : world.walls) w.advance(static_cast<double>(now) * dt_tick, static_cast<double>(t - now) * dt_tick);
    walls_at(world, t);
    world.time = static_cast<double>(t) * dt_tick;
    lists_stale_ = lists_stale_ || forces.walls_moved(world);
    collect_active(t);
    const Predictor kin = predictor(world, t);
    for (std::size_t q = 0; q < active_.size() && !lists_stale_; ++q) lists_stale_ = list_outrun(world, kin, active_[q]);
    if (lists_stale_) rebuild_lists(world, forces, t);
    predict_around(world, t, 0);
    const std::size_t due = active_.size();
    wake(world, t);
    predict_around(world, t, due);  // the woken particles' partners
    contacts_before.resize(active_.size());
    for (std::size_t q = 0; q < active_.size(); ++q) contacts_before[q] = world.particles.contact_count[active_[q]];
    evaluate(world, forces, t);
    correct(world, forces, t, contacts_before);
    choose_levels(world, forces, t, contacts_before);
    for (std::uint32_t i : active_) is_active_[i] = 0;
    ++stats_.block_times;
    now = t;
  }
  next_step(world);
}

std::vector<std::size_t> BlockHermite::level_histogram() const {
  std::vector<std::size_t> h(members_.size());
  for (std::size_t k = 0; k < members_.size(); ++k) h[k] = members_[k].size();
  return h;
}

std::uint64_t BlockHermite::particle_evaluations() const {
  return std::accumulate(stats_.evaluations.begin(), stats_.evaluations.end(), std::uint64_t{0});
}

}  // namespace tsubu
