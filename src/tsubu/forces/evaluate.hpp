// ForceField's one contact evaluation, for the force field's own files: geometry -> law ->
// history -> per-contact results, written once on the number type. On double it is a fixed
// step from the particles' current state; on Dual (core/dual.hpp) it is a block step from
// the predicted state, and the rate channel adds each contact's rates and step bound (the
// Rates record). Pairs go in blocks of lanes, one array per scalar, so that the loop over
// their laws is a vector loop; walls go one at a time.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "tsubu/contact/pair_geometry.hpp"
#include "tsubu/forces/force_field.hpp"

namespace tsubu {

// A particle's motion as the laws see it: its position, and its velocity and spin on the
// number type (on Dual with their rates, the accelerations).
template <class T>
struct Motion {
  Vec3 x;
  Vector<T> v, w;
};
// The same on double, read in place from the particles' arrays (no copy on the fixed steps'
// path).
struct MotionInPlace {
  const Vec3 &x, &v, &w;
};

// The kinematics of a fixed step: the particles' current state; every contact advances by dt.
struct CurrentState {
  using Number = double;
  const Particles& p;
  double dt;
  MotionInPlace at(std::size_t i) const { return {p.position[i], p.velocity[i], p.omega[i]}; }
  double step(std::size_t, std::size_t) const { return dt; }
  double step(std::size_t) const { return dt; }
};

// The kinematics of a block step: every particle predicted to the evaluation time; a contact
// advances by the time since the later of its particles' last evaluations (their shared step).
struct PredictedState {
  using Number = Dual;
  const Predictor& kin;
  Motion<Dual> at(std::size_t i) const {
    const Kinematics k = kin.at(i);
    return {k.x, DualVec3(k.v, k.a), DualVec3(k.w, k.alpha)};
  }
  double step(std::size_t i, std::size_t j) const { return kin.since(std::max(kin.time[i], kin.time[j])); }
  double step(std::size_t i) const { return kin.since(kin.time[i]); }
};

// A position or distance on the number type: on Dual it carries its rate (on double it is x
// itself, not a copy).
template <class T>
decltype(auto) with_rate(const Vec3& x, const Vec3& rate) {
  if constexpr (std::is_same_v<T, double>) return x;
  else return DualVec3(x, rate);
}
template <class T>
T with_rate(double x, double rate) {
  if constexpr (std::is_same_v<T, double>) return x;
  else return Dual(x, rate);
}

// Where the particle `a` touches `wall` (t, found on double; on a mesh at its nearest feature
// `kind`, an edge's index `edge`) on the number type: on Dual with the rates of the distance
// and the normal. A whole plane's normal stands still and its distance changes at the
// particle's velocity along it relative to the surface's (v_rel); a curved wall's (a
// cylinder, a cone, a hole's rim) is the touch on Dual of the centre moving relative to the
// wall (Wall::touch_on); a mesh's follows its nearest feature (touch_triangle_with_rates).
template <class T, class Motion>
BasicWallTouch<T> touch_with_rates(const Wall& wall, const Motion& a, const WallTouch& t, const Vector<T>& v_rel,
                                   NearestFeature::Kind kind = NearestFeature::face, std::uint32_t edge = 0) {
  if constexpr (std::is_same_v<T, double>) return t;
  else if (wall.whole_plane()) return {Dual(t.distance, dot(value(v_rel), t.normal)), t.normal};
  else if (wall.mesh) return touch_triangle_with_rates(wall, kind, edge, t, a.x, value(a.v));
  else return wall.touch_on<Dual>(DualVec3(a.x, value(a.v) - wall.velocity));
}

// The velocity of a wall's surface under the particle `a` (Wall::surface_velocity_at, t its
// touch, kind and edge as above); on Dual with its rate: the wall's own velocity is constant
// within a step, a turning surface's changes as the point under the particle moves: on a
// whole plane with the particle's velocity, on a curved wall or a mesh with the rate of the
// nearest point, x - distance normal (`moving`: the touch with its rates), relative to the
// axis, which moves with the wall; a mesh conveyor's with the rate of the contact's plane.
template <class T, class Motion>
Vector<T> surface_velocity(const Wall& wall, const Motion& a, const WallTouch& t,
                           NearestFeature::Kind kind = NearestFeature::face, std::uint32_t edge = 0) {
  if constexpr (std::is_same_v<T, double>) {
    return wall.surface_velocity_at(a.x, t);
  } else {
    const Vec3 u = wall.surface_velocity_at(a.x, t);
    if (!wall.surface_moves()) return DualVec3(u, {});
    if (wall.whole_plane()) return DualVec3(u, cross(wall.angular_velocity, value(a.v)));
    const BasicWallTouch<Dual> moving = touch_with_rates<Dual>(wall, a, t, DualVec3{}, kind, edge);
    if (wall.mesh && !(wall.surface_velocity == Vec3{})) {  // a conveyor's v_s - (v_s . n) n as n turns
      const Vec3 n = value(moving.normal), n_rate = rate(moving.normal), &s = wall.surface_velocity;
      return DualVec3(u, -dot(s, n_rate) * n - dot(s, n) * n_rate);
    }
    const Vec3 nearest_point_rate = rate(DualVec3(a.x, value(a.v)) - moving.distance * moving.normal);
    return DualVec3(u, cross(wall.angular_velocity, nearest_point_rate - wall.velocity));
  }
}

// The law's models, called on the number type T: every law on double; on Dual only the laws
// whose normal model has rates (compute_active refuses a table with another).
template <class T, class Visit>
void visit_law(const PairLaw& law, Visit&& visit) {
  std::visit(
      [&](const auto& normal, const auto& tangential, const auto& rolling) {
        if constexpr (std::is_same_v<T, double> || has_rates_v<std::decay_t<decltype(normal)>>)
          visit(normal, tangential, rolling);
      },
      law.normal, law.tangential, law.rolling);
}

// The law on the number type: the force (evaluate), or on Dual the force with its rates
// (evaluate_with_rates). The history advances alike.
template <class Normal, class Tangential, class Rolling, class T>
[[gnu::always_inline]] inline auto evaluate_law(const Normal& normal, const Tangential& tangential, const Rolling& rolling,
                                                const BasicContactGeometry<T>& g, ContactHistory& h) {
  if constexpr (std::is_same_v<T, double>) return evaluate(normal, tangential, rolling, g, h);
  else return evaluate_with_rates(normal, tangential, rolling, g, h);
}

// The rate channel's step bound of a contact (ContactStepRules): touching, the shorter of
// kappa_c times its collision time at the current approach speed and half a period of its
// current stiffness; apart, the time to close the gap, never below the step it would get on
// touching. (The dashpots' bound is a particle's: see compute_active.) The collision time (a
// fifth root for Hertz) is computed only when it is the bound.
template <class Normal>
double contact_step(const Normal& normal, const ContactStepRules& rules, double m_eff, double r_eff, bool touching,
                    double v_approach, double stiffness, double gap, double a_approach) {
  const double u = std::max(v_approach, rules.u_floor);
  const auto impact = [&] { return rules.kappa_c * normal.collision_time(m_eff, r_eff, u); };
  if (!touching) {
    const double closing = rules.eta_gap * time_to_close(gap, v_approach, a_approach);
    return collision_longer_than(normal, m_eff, r_eff, u, closing / rules.kappa_c) ? impact() : closing;
  }
  if (!(stiffness > 0)) return impact();
  const double spring = rules.kappa_c * M_PI * std::sqrt(m_eff / stiffness);
  return collision_longer_than(normal, m_eff, r_eff, u, spring / rules.kappa_c) ? spring : impact();
}

// The rolling spring k_r (N m/rad) as the contact rule sees it: the normal stiffness whose
// half period, with the contact's m_eff, is the half period of the spring turning the two
// bodies against each other about their centres (rotation rate k_r (1/I_i + 1/I_j),
// `turning`; a wall's body turns alone). Turning about the centre, not the contact point
// (I + m R^2, which the rolling dashpot's C_r uses), makes it the faster of the two: the
// rule is safe for a grain that slides as for one that rolls.
inline double rolling_equivalent_stiffness(double k_r, double m_eff, double turning) { return k_r * m_eff * turning; }

// How long ago a contact that is found touching, and was not at its last evaluation, began:
// its overlap over its rate of overlap (the approach speed at touch, less what the contact
// has braked since: within a few per cent over one contact step). 0 when not approaching.
inline double onset_age(Dual delta) { return delta.d > 0 ? delta.v / delta.d : 0.0; }
// How long ago a contact that was touching at its last evaluation, and is not now, ended: its
// gap over its rate of opening (the grains fly apart free since). 0 when it is not opening.
inline double release_age(double gap, double opening) { return opening > 0 ? gap / opening : 0.0; }

// The time over which a contact's springs (tangential, rolling) advance in a block step: the
// step since the contact was last evaluated, or for a contact that began within it (not
// touching then, and handed no history by a neighbouring triangle) the time since its onset,
// so that its first stretch counts the touching part of the step only.
inline double spring_step(double step, bool was_touching, const ContactHistory& h, Dual delta) {
  const bool fresh = !was_touching && h.xi == Vec3{} && h.rolling == Vec3{} && h.normal[0] == 0 && h.normal[1] == 0;
  return fresh ? std::min(step, onset_age(delta)) : step;
}

// One scalar of the number type in a lane: a Dual as its two doubles, left uninitialised like
// a double (a lane is written before it is read).
struct DualSlot {
  double v, d;
  DualSlot& operator=(Dual x) { return v = x.v, d = x.d, *this; }
  operator Dual() const { return {v, d}; }
};
template <class T>
using Slot = std::conditional_t<std::is_same_v<T, double>, double, DualSlot>;

// A particle's moment of inertia about a point of its surface, I + m R^2: the rolling
// inertia of a contact (BasicContactGeometry::rolling_inertia) from its two bodies'.
inline double rolling_inertia(const Particles& p, std::size_t i) { return p.inertia[i] + p.mass[i] * p.radius[i] * p.radius[i]; }

// A block of touching pairs held as one array per scalar ("lanes"), so that the loop over
// the block's laws is a vector loop: each iteration reads and writes its own lane only.
template <std::size_t N, class T>
struct Lanes {
  // Fixed steps advance every contact by the one dt, block steps each by its own.
  static constexpr bool kOneStep = std::is_same_v<T, double>;
  Slot<T> n[3][N], delta[N], v_n[N], v_t[3][N], w_roll[3][N];   // BasicContactGeometry
  double r_eff[N], m_eff[N], d_mean[N], d_small[N], dt[kOneStep ? 1 : N], rolling_inertia[N];
  double xi[3][N], normal[2][N], rolling[3][N];                  // ContactHistory
  Slot<T> total[3][N], tangential[3][N], rolling_torque[3][N];   // the law's force and rolling torque on i
  double energy[N], gap_shift[N];                                // ContactForce
  double stiffness[N], damping[N], tangential_damping[N];        // ContactForceRate
  double rolling_stiffness[N], rolling_damping[N];

  static Vector<T> get(const Slot<T> (&a)[3][N], std::size_t b) { return {T(a[0][b]), T(a[1][b]), T(a[2][b])}; }
  static void put(Slot<T> (&a)[3][N], std::size_t b, const Vector<T>& v) { a[0][b] = v.x, a[1][b] = v.y, a[2][b] = v.z; }
  // The same for the arrays of doubles whatever T (history).
  static Vec3 get_plain(const double (&a)[3][N], std::size_t b) { return {a[0][b], a[1][b], a[2][b]}; }
  static void put_plain(double (&a)[3][N], std::size_t b, const Vec3& v) { a[0][b] = v.x, a[1][b] = v.y, a[2][b] = v.z; }

  void set_geometry(std::size_t b, const BasicContactGeometry<T>& g, double step) {
    put(n, b, g.n), put(v_t, b, g.v_t), put(w_roll, b, g.w_roll);
    delta[b] = g.delta, v_n[b] = g.v_n, r_eff[b] = g.r_eff, m_eff[b] = g.m_eff, d_mean[b] = g.d_mean, d_small[b] = g.d_small;
    dt[kOneStep ? 0 : b] = step, rolling_inertia[b] = g.rolling_inertia;
  }
  BasicContactGeometry<T> geometry(std::size_t b) const {
    return {get(n, b), T(delta[b]), T(v_n[b]), get(v_t, b), r_eff[b], m_eff[b], d_mean[b], d_small[b], dt[kOneStep ? 0 : b],
            get(w_roll, b), rolling_inertia[b]};
  }
  void set_history(std::size_t b, const ContactHistory& h) {
    put_plain(xi, b, h.xi), normal[0][b] = h.normal[0], normal[1][b] = h.normal[1], put_plain(rolling, b, h.rolling);
  }
  ContactHistory history(std::size_t b) const { return {get_plain(xi, b), {normal[0][b], normal[1][b]}, get_plain(rolling, b)}; }
  void set_force(std::size_t b, const ContactForce& f) {
    put(total, b, f.total), put(tangential, b, f.tangential), energy[b] = f.energy, gap_shift[b] = f.gap_shift;
    put(rolling_torque, b, f.rolling);
  }
  void set_force(std::size_t b, const ContactForceRate& f) {
    put(total, b, f.total), put(tangential, b, f.tangential), energy[b] = f.energy;
    stiffness[b] = f.stiffness, damping[b] = f.damping, tangential_damping[b] = f.tangential_damping;
    put(rolling_torque, b, f.rolling.torque);
    rolling_stiffness[b] = f.rolling.stiffness, rolling_damping[b] = f.rolling.damping;
  }
  // The law of every lane: a vector loop (the LawLoopVectorises test checks that it is one).
  template <class Normal, class Tangential, class Rolling>
  void evaluate_all(std::size_t m, const Normal& normal_model, const Tangential& tangential_model, const Rolling& rolling_model) {
#pragma omp simd
    for (std::size_t b = 0; b < m; ++b) evaluate_one(b, normal_model, tangential_model, rolling_model);
  }
  template <class Normal, class Tangential, class Rolling>
  [[gnu::always_inline]] void evaluate_one(std::size_t b, const Normal& normal_model, const Tangential& tangential_model,
                                           const Rolling& rolling_model) {
    ContactHistory h = history(b);
    set_force(b, evaluate_law(normal_model, tangential_model, rolling_model, geometry(b), h));
    set_history(b, h);
  }
};

// The pair-list entries of a block: a range of the list (fixed steps) or the indices of the
// pairs an active particle evaluates (block steps).
struct ListRange {
  std::size_t begin, end;
  std::size_t size() const { return end - begin; }
  std::size_t operator[](std::size_t e) const { return begin + e; }
};
struct ListIndices {
  const std::uint32_t* index;
  std::size_t count;
  std::size_t size() const { return count; }
  std::size_t operator[](std::size_t e) const { return index[e]; }
};

template <class State, class Entries>
void ForceField::evaluate_pair_block(World& world, const State& state, const Entries& entries, const PairLaw* shared,
                                     const ContactStepRules* rules) {
  using T = typename State::Number;
  constexpr bool kRates = std::is_same_v<T, Dual>;
  const Particles& p = world.particles;
  auto& contacts = world.contacts.pairs();
  const auto law_of = [&](const Contact& c) -> const PairLaw& { return model_->laws.at(p.material[c.i], p.material[c.j]); };
  // Scalar pass: which entries touch. The touching ones are listed; the rest have their
  // history and results cleared (fixed steps: every entry's result is cleared and its history
  // kept only if it touches, without a branch on touching, which is unpredictable).
  std::uint32_t touching[kBlock];
  bool was_touching[kBlock];  // at the contact's last evaluation
  Vec3 separation[kBlock];
  std::size_t m = 0;
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const std::size_t k = entries[e];
    Contact& c = contacts[k];
    const auto a = state.at(c.i), b = state.at(c.j);
    const Vec3 d = world.domain.separation(a.x, b.x);
    const double reach = p.radius[c.i] + p.radius[c.j];
    const double dist2 = norm2(d);
    if constexpr (kRates) was_touching[m] = c.touching;
    c.touching = dist2 < reach * reach;
    if constexpr (kRates) {
      if (!c.touching) {
        // The rate channel of a pair apart: no force, and the step bound of its approach.
        const double dist = std::sqrt(dist2);
        c.history = {};
        pair_results_.set(k, {}, {}, 0, 0);
        if (rolls_) pair_results_.rolling_i[k] = {};
        const Vec3 n = d / dist;
        const double gap = dist - reach, opening = dot(value(a.v) - value(b.v), n);
        const double released = was_touching[m] ? release_age(gap, opening) : 0;
        const double m_eff = p.mass[c.i] * p.mass[c.j] / (p.mass[c.i] + p.mass[c.j]);
        const double r_eff = p.radius[c.i] * p.radius[c.j] / reach;
        visit_law<T>(law_of(c), [&](const auto& normal, const auto&, const auto&) {
          pair_rates_[k] = {{}, {}, 0,
                            contact_step(normal, *rules, m_eff, r_eff, false, -opening, 0, gap,
                                         -dot(rate(a.v) - rate(b.v), n)),
                            n, 0, 0, 0, released};
        });
      }
    } else {
      const double keep = c.touching;
      c.history.xi *= keep;
      c.history.normal[0] *= keep, c.history.normal[1] *= keep;
      c.history.rolling *= keep;
      pair_results_.set(k, {}, {}, 0, 0);
      if (rolls_) pair_results_.rolling_i[k] = {};
    }
    touching[m] = static_cast<std::uint32_t>(k);
    separation[m] = d;
    m += c.touching;
  }
  if constexpr (!kRates)
    if (shifts_)
      for (std::size_t e = 0; e < entries.size(); ++e) pair_results_.shift_i[entries[e]] = pair_results_.shift_j[entries[e]] = {};
  // The touching pairs' geometry and history (the laws', stored from i) go into lanes.
  Lanes<kBlock, T> lanes;
  for (std::size_t b = 0; b < m; ++b) {
    const Contact& c = contacts[touching[b]];
    const auto mi = state.at(c.i), mj = state.at(c.j);
    const auto& d = with_rate<T>(separation[b], value(mi.v) - value(mj.v));
    BasicContactGeometry<T> g =
        pair_geometry<T>(p.radius[c.i], p.radius[c.j], p.mass[c.i], p.mass[c.j], d, mi.v, mj.v, mi.w, mj.w);
    if (rolls_) g.rolling_inertia = 1 / (1 / rolling_inertia(p, c.i) + 1 / rolling_inertia(p, c.j));  // read by epsd only
    double step = state.step(c.i, c.j);
    if constexpr (kRates) step = spring_step(step, was_touching[b], c.history, g.delta);
    lanes.set_geometry(b, g, step);
    lanes.set_history(b, c.history);
  }
  if (shared) {
    visit_law<T>(*shared, [&](const auto& normal, const auto& tangential, const auto& rolling) {
      lanes.evaluate_all(m, normal, tangential, rolling);
    });
  } else {
    for (std::size_t b = 0; b < m; ++b)
      visit_law<T>(law_of(contacts[touching[b]]),
                   [&](const auto& nm, const auto& tm, const auto& rm) { lanes.evaluate_one(b, nm, tm, rm); });
  }
  // The results (and the histories) back to their contacts.
  for (std::size_t b = 0; b < m; ++b) {
    const std::size_t k = touching[b];
    Contact& c = contacts[k];
    c.history = lanes.history(b);
    const Vector<T> n = lanes.get(lanes.n, b), total = lanes.get(lanes.total, b);
    const Vector<T> n_x_ft = cross(n, lanes.get(lanes.tangential, b));
    const T delta = lanes.delta[b];
    pair_results_.set(k, value(total), value(n_x_ft), value(delta), lanes.energy[b]);
    if (rolls_) pair_results_.rolling_i[k] = value(lanes.get(lanes.rolling_torque, b));
    if constexpr (kRates) {
      const double v_n = T(lanes.v_n[b]).v;
      const double stiffness =
          rolls_ ? std::max(lanes.stiffness[b], rolling_equivalent_stiffness(lanes.rolling_stiffness[b], lanes.m_eff[b],
                                                                             1 / p.inertia[c.i] + 1 / p.inertia[c.j]))
                 : lanes.stiffness[b];
      visit_law<T>(law_of(c), [&](const auto& normal, const auto&, const auto&) {
        pair_rates_[k] = {rate(total), rate(n_x_ft), delta.d,
                          contact_step(normal, *rules, lanes.m_eff[b], lanes.r_eff[b], true, -v_n, stiffness, 0, 0),
                          value(n), lanes.damping[b], lanes.tangential_damping[b], was_touching[b] ? 0 : onset_age(delta)};
      });
      if (rolls_)
        pair_rates_[k].rolling_i = rate(lanes.get(lanes.rolling_torque, b)), pair_rates_[k].rolling_damping = lanes.rolling_damping[b];
    } else if (shifts_) {  // models P and F: split like an impulse, the centre of mass stays where it is
      const double shift = lanes.gap_shift[b] * lanes.m_eff[b];
      pair_results_.shift_i[k] = (shift / p.mass[c.i]) * n;
      pair_results_.shift_j[k] = (-shift / p.mass[c.j]) * n;
    }
  }
}

template <class State>
void ForceField::evaluate_wall(World& world, const State& state, std::size_t k, const ContactStepRules* rules) {
  const Contact& c = world.contacts.walls()[k];
  visit_law<typename State::Number>(model_->laws.at(world.particles.material[c.i], world.walls[wall_of_contact(world, k)].material),
                                    [&](const auto& normal, const auto& tangential, const auto& rolling) {
                                      evaluate_wall(world, state, k, normal, tangential, rolling, rules);
                                    });
}

template <class State, class Normal, class Tangential, class Rolling>
void ForceField::evaluate_wall(World& world, const State& state, std::size_t k, const Normal& normal,
                               const Tangential& tangential, const Rolling& rolling, const ContactStepRules* rules) {
  using T = typename State::Number;
  constexpr bool kRates = std::is_same_v<T, Dual>;
  const Particles& p = world.particles;
  Contact& c = world.contacts.walls()[k];
  const std::size_t i = c.i;
  const Wall& wall = world.walls[wall_of_contact(world, k)];
  const double r = p.radius[i];
  const auto a = state.at(i);
  // With meshes, where it touches was found before (touch_walls, touch_particle_walls).
  const bool found = !world.wall_elements.empty();
  const WallTouch touch = found ? wall_touch_[k].touch : wall.touch(a.x);
  const NearestFeature::Kind kind = found ? wall_touch_[k].kind : NearestFeature::face;
  const std::uint32_t feature = found ? wall_touch_[k].feature : 0;
  const Vec3& n = touch.normal;
  const Vector<T> v_rel = a.v - surface_velocity<T>(wall, a, touch, kind, feature);
  const double dist = touch.distance;
  // Touching from the front side only: a centre behind the surface has tunnelled through and
  // feels no force from it. A mesh's triangle may leave the contact to another (world/mesh.hpp).
  const bool was_touching = c.touching;
  const bool counts = !found || wall_touch_[k].counts;  // a mesh's triangle may not count it
  c.touching = dist < r && dist > 0 && counts;
  if (!c.touching) {
    c.history = {};
    if constexpr (kRates) {  // the rate channel: the step bound of a grain in front of the wall
      const double opening = dot(value(v_rel), n);
      const double released = was_touching ? release_age(dist - r, opening) : 0;
      const double bound = dist > 0 && counts ? contact_step(normal, *rules, p.mass[i], r, false, -opening, 0, dist - r,
                                                   -dot(rate(v_rel), n))
                                    : std::numeric_limits<double>::infinity();
      wall_rates_[k] = {{}, {}, 0, bound, n, 0, 0, 0, released};
    } else if (shifts_) {
      wall_results_.shift_i[k] = {};
    }
    wall_results_.set(k, {}, {}, 0, 0);
    if (rolls_) wall_results_.rolling_i[k] = {};
    return;
  }
  const BasicWallTouch<T> moving = touch_with_rates<T>(wall, a, touch, v_rel, kind, feature);
  BasicContactGeometry<T> g = wall_geometry<T>(r, p.mass[i], moving.normal, moving.distance, v_rel, a.w);
  g.dt = state.step(i);
  if constexpr (kRates) g.dt = spring_step(g.dt, was_touching, c.history, g.delta);
  if (rolls_) g.rolling_inertia = rolling_inertia(p, i);
  const auto f = evaluate_law(normal, tangential, rolling, g, c.history);
  const Vector<T> n_x_ft = cross(g.n, f.tangential);
  wall_results_.set(k, value(f.total), value(n_x_ft), value(g.delta), f.energy);
  if constexpr (kRates) {
    const double stiffness =
        rolls_ ? std::max(f.stiffness, rolling_equivalent_stiffness(f.rolling.stiffness, p.mass[i], 1 / p.inertia[i]))
               : f.stiffness;
    wall_rates_[k] = {rate(f.total), rate(n_x_ft), g.delta.d,
                      contact_step(normal, *rules, p.mass[i], r, true, -g.v_n.v, stiffness, 0, 0), n, f.damping,
                      f.tangential_damping, was_touching ? 0 : onset_age(g.delta)};
    if (rolls_) wall_results_.rolling_i[k] = value(f.rolling.torque), wall_rates_[k].rolling_i = rate(f.rolling.torque),
                wall_rates_[k].rolling_damping = f.rolling.damping;
  } else {
    if (shifts_) wall_results_.shift_i[k] = f.gap_shift * g.n;  // zero for models that do not correct
    if (rolls_) wall_results_.rolling_i[k] = f.rolling;
  }
}

}  // namespace tsubu
