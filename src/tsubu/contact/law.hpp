// The contact law of one material pair: a normal, a tangential and a rolling model. The
// force loop dispatches on the variants' alternatives once per loop when every pair uses
// the same models (the common case), so the per-contact code is a direct, inlined call.
//
// The three variants are the registry of the laws: the loader, make_pair_law and the time
// scales find a law by its traits (contact/law_traits.hpp) through them, so that a law is
// registered by adding it here (docs/contact-laws.md).
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "tsubu/contact/energy_conserving.hpp"
#include "tsubu/contact/hooke_hysteresis.hpp"
#include "tsubu/contact/law_traits.hpp"
#include "tsubu/contact/normal_models.hpp"
#include "tsubu/contact/rolling_models.hpp"
#include "tsubu/contact/tangential_models.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

using NormalModel =
    std::variant<LinearDashpot, HertzTsuji, HertzSediment, HookeHysteresis, EnergyConserving, EnergyConserving2005>;
using TangentialModel = std::variant<NoFriction, LinearCoulomb, MindlinSlip>;
using RollingModel = std::variant<NoRolling, ConstantDirectionalTorque, ElasticPlasticRolling>;

// Their traits, in the variants' order (the order the scenario's messages list them in).
inline constexpr auto kNormalLaws = traits_of_all<NormalModel>();
inline constexpr auto kTangentialLaws = traits_of_all<TangentialModel>();
inline constexpr auto kRollingLaws = traits_of_all<RollingModel>();

// Models whose force is a smooth function of the kinematics, written on the number type:
// they give exact rates (Hermite integration). Models P, F and HH are defined on fixed steps.
template <class Normal>
constexpr bool has_rates_v = requires(const Normal& n, const DualContactGeometry& g, ContactHistory& h) { n.force(g, h); };

// A law is well formed: checked at compile time for every registered law (law.cpp) and for
// a law a test registers. A normal law's history slots are ContactHistory::normal[0..] and
// keep on a swap, a tangential law's the spring xi, which is negated (the transforms
// world/contact_list.hpp lists at Contact, and no other: with them a pair's force does not
// depend on which of its particles the laws see it from); a law runs with block steps
// exactly when its force has rates. A rolling law's one slot is ContactHistory::rolling,
// negated on a swap; every rolling law has rates (its torque is written on the number type).
template <class Law>
constexpr bool well_formed_normal_law() {
  constexpr LawTraits t = traits_of<Law>();
  static_assert(t.history.size() <= std::size(ContactHistory{}.normal), "more history slots than ContactHistory::normal");
  static_assert([] {
    for (const HistorySlot& h : traits_of<Law>().history)
      if (h.swap != Swap::keep) return false;
    return true;
  }(), "a normal history slot must keep on a swap (or be listed at Contact, world/contact_list.hpp)");
  static_assert(t.allows("block_hermite") == has_rates_v<Law>, "block steps need rates: declare integrators = {kFixedSteps}");
  return true;
}
template <class Law>
constexpr bool well_formed_tangential_law() {
  static_assert(traits_of<Law>().history.size() <= 1, "a tangential law's one history slot is the spring xi");
  static_assert(traits_of<Law>().history.empty() || traits_of<Law>().history[0].swap == Swap::negate,
                "the spring xi is negated on a swap");
  return true;
}

template <class Law>
constexpr bool well_formed_rolling_law() {
  static_assert(traits_of<Law>().history.size() <= 1, "a rolling law's one history slot is ContactHistory::rolling");
  static_assert(traits_of<Law>().history.empty() || traits_of<Law>().history[0].swap == Swap::negate,
                "the rolling spring is negated on a swap");
  static_assert(requires(const Law& l, const DualContactGeometry& g, const BasicNormalForce<Dual>& fn, DualVec3& h) {
    l.torque(g, fn, h);
  }, "a rolling law's torque is written on the number type (block steps take its rates)");
  static_assert(traits_of<Law>().allows("block_hermite"), "every integrator takes a rolling law");
  return true;
}

struct PairLaw {
  NormalModel normal;
  TangentialModel tangential;
  RollingModel rolling;
};

// Force on particle i (normal + tangential), the tangential part alone (for torques) and
// the rolling torque on i (j takes it negated).
struct ContactForce {
  Vec3 total;
  Vec3 tangential;
  double energy = 0;
  double gap_shift = 0;  // m, see NormalForce
  Vec3 rolling;
};

template <class Normal, class Tangential, class Rolling>
[[gnu::always_inline]] inline ContactForce evaluate(const Normal& normal, const Tangential& tangential, const Rolling& rolling,
                                                    const ContactGeometry& g, ContactHistory& h) {
  const NormalForce fn = normal.force(g, h);
  const Vec3 ft = tangential.force(g, fn, h.xi);
  return {fn.f * g.n + ft, ft, fn.energy, fn.gap_shift, rolling.torque(g, fn, h.rolling).torque};
}

// The same law run on Duals: the force on particle i, its tangential part and the rolling
// torque on i, each with its time derivative along the kinematics that `g` carries. The
// history is advanced as by evaluate().
struct ContactForceRate {
  DualVec3 total, tangential;
  double energy = 0;
  double stiffness = 0;  // linear-equivalent normal stiffness now, N/m
  double damping = 0;    // normal damping coefficient now, N s/m
  double tangential_damping = 0;  // the tangential dashpot's coefficient, N s/m
  BasicRollingTorque<Dual> rolling;
};
template <class Normal, class Tangential, class Rolling>
inline ContactForceRate evaluate_with_rates(const Normal& normal, const Tangential& tangential, const Rolling& rolling,
                                            const DualContactGeometry& g, ContactHistory& h) {
  const BasicNormalForce<Dual> fn = normal.force(g, h);
  DualVec3 xi(h.xi), spring(h.rolling);
  const DualVec3 ft = tangential.force(g, fn, xi);
  const BasicRollingTorque<Dual> torque = rolling.torque(g, fn, spring);
  h.xi = value(xi), h.rolling = value(spring);
  return {fn.f * g.n + ft, ft, fn.energy.v, fn.stiffness.v, fn.damping.v, tangential.dashpot_ratio() * fn.damping.v, torque};
}

// A dt below this share of a contact's duration resolves it (20 steps per contact; the
// suggestion of `tsubu check`); a contact of fewer steps may be an error of dt.
constexpr double kStepsPerContact = 20;

// How long a collision of the model lasts at approach speed u (m_eff, r_eff: the pair's
// effective mass and radius). The linear springs' half period does not depend on u; for
// model HH it is the half period of its stiffest line, k2max, which unloading follows after a
// deep contact.
double contact_time(const NormalModel& model, double m_eff, double r_eff, double u);
// The overlap at which a head-on collision at approach speed u stops, elastically (without
// damping, which makes it shallower): u sqrt(m*/k) for the linear springs (model HH: its
// loading line k_n), (15 m* u^2 / (16 E* sqrt(R*)))^(2/5) for Hertz.
double peak_overlap(const NormalModel& model, double m_eff, double r_eff, double u);

// Whether a collision at approach speed u lasts longer than t: the law's own test where it
// has one that spares the collision time's cost (Hertz: no fifth root), else the comparison.
template <class Normal>
bool collision_longer_than(const Normal& normal, double m_eff, double r_eff, double u, double t) {
  if constexpr (requires { normal.collision_longer_than(m_eff, r_eff, u, t); })
    return normal.collision_longer_than(m_eff, r_eff, u, t);
  else
    return normal.collision_time(m_eff, r_eff, u) > t;
}

// The normal law's name in messages ("hertz_tsuji (T)").
std::string_view label_of(const NormalModel& model);
// Whether the law gives its restitution in a fixed number of steps whatever dt (models P and
// F: `exact_whatever_dt`), so that a contact of few steps is no error of dt.
bool exact_whatever_dt(const NormalModel& model);
// What a non-finite force of the law means (`when_not_finite`), or "".
std::string_view when_not_finite(const NormalModel& model);

// What a scenario says about a material pair, before the materials are known: the laws by
// name, the generic keys, and the values of the laws' own keys (those left out take their
// defaults when the law is built).
struct ContactSpec {
  std::string normal = "hertz_tsuji";  // a name of kNormalLaws
  std::string tangential = "mindlin";  // a name of kTangentialLaws
  std::string rolling = "none";        // a name of kRollingLaws
  double restitution = 1.0;            // e in (0, 1]
  double friction = 0.0;               // mu
  LawValues values;                    // the laws' keys: "stiffness", "alpha", ...
};

// The law of `Variant` named `name`, built from its keys' values and the pair; `side` is what
// a tangential law takes of the normal one. Throws std::invalid_argument for a name the
// variant lacks, and for a value out of its key's range or a required key not given.
template <class Variant, class... Side>
Variant build_law(std::string_view name, const MaterialPair& pair, const LawValues& values, const Side&... side) {
  std::optional<Variant> law;
  for_each_law<Variant>([&]<class Law>(std::type_identity<Law>) {
    if (!law && Law::name == name) law = Law::build(LawInput(pair, values, traits_of<Law>()), side...);
  });
  if (!law) throw std::invalid_argument("no law is named \"" + std::string(name) + "\"");
  return *std::move(law);
}

// Builds the law for materials a and b. Throws std::invalid_argument for combinations that
// the scenario validator should have refused, and for a value of a key that neither law has.
PairLaw make_pair_law(const ContactSpec& spec, const Material& a, const Material& b);

// The table of laws indexed [a * n + b] for n materials.
struct LawTable {
  int n_materials = 0;
  std::vector<PairLaw> laws;
  const PairLaw& at(int a, int b) const { return laws[static_cast<std::size_t>(a * n_materials + b)]; }
  // True when some law's normal model corrects positions (models P, F).
  bool corrects_positions() const;
  // True when some law has a rolling model (not "none").
  bool resists_rolling() const;
  // A normal model in the table that has no rates (block steps cannot run it), as
  // "normal model <label>", or "" when every law has them.
  std::string without_rates() const;
};

}  // namespace tsubu
