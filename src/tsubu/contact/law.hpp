// The contact law of one material pair: a normal and a tangential model. The force loop
// dispatches on the pair of variant alternatives once per loop when every pair uses the
// same models (the common case), so the per-contact code is a direct, inlined call.
#pragma once
#include <string>
#include <variant>
#include <vector>

#include "tsubu/contact/energy_conserving.hpp"
#include "tsubu/contact/normal_models.hpp"
#include "tsubu/contact/tangential_models.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

using NormalModel =
    std::variant<LinearDashpot, HertzTsuji, HertzSediment, HookeHysteresis, EnergyConserving, EnergyConserving2005>;
using TangentialModel = std::variant<NoFriction, LinearCoulomb, MindlinSlip>;

struct PairLaw {
  NormalModel normal;
  TangentialModel tangential;
};

// Force on particle i (normal + tangential) and the tangential part alone (for torques).
struct ContactForce {
  Vec3 total;
  Vec3 tangential;
  double energy = 0;
  double gap_shift = 0;  // m, see NormalForce
};

template <class Normal, class Tangential>
[[gnu::always_inline]] inline ContactForce evaluate(const Normal& normal, const Tangential& tangential,
                             const ContactGeometry& g, ContactHistory& h) {
  const NormalForce fn = normal.force(g, h);
  const Vec3 ft = tangential.force(g, fn, h.xi);
  return {fn.f * g.n + ft, ft, fn.energy, fn.gap_shift};
}

// Models whose force is a smooth function of the kinematics, written on the number type:
// they give exact rates (Hermite integration). Models P, F and HH are defined on fixed steps.
template <class Normal>
constexpr bool has_rates_v = requires(const Normal& n, const DualContactGeometry& g, ContactHistory& h) { n.force(g, h); };

// The same law run on Duals: the force on particle i and its tangential part, each with its
// time derivative along the kinematics that `g` carries. The history is advanced as by
// evaluate().
struct ContactForceRate {
  DualVec3 total, tangential;
  double energy = 0;
  double stiffness = 0;  // linear-equivalent normal stiffness now, N/m
  double damping = 0;    // normal damping coefficient now, N s/m
  double tangential_damping = 0;  // the tangential dashpot's coefficient, N s/m
};
template <class Normal, class Tangential>
inline ContactForceRate evaluate_with_rates(const Normal& normal, const Tangential& tangential,
                                            const DualContactGeometry& g, ContactHistory& h) {
  const BasicNormalForce<Dual> fn = normal.force(g, h);
  DualVec3 xi(h.xi);
  const DualVec3 ft = tangential.force(g, fn, xi);
  h.xi = value(xi);
  return {fn.f * g.n + ft, ft, fn.energy.v, fn.stiffness.v, fn.damping.v, tangential.dashpot_ratio() * fn.damping.v};
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

// What a scenario says about a material pair, before the materials are known.
struct ContactSpec {
  std::string normal = "hertz_tsuji";  // linear | hertz_tsuji | hertz_sediment | hooke_hysteresis | energy_conserving[_2005]
  std::string tangential = "mindlin";  // none | linear_coulomb | mindlin
  double restitution = 1.0;            // e in (0, 1]
  double friction = 0.0;               // mu
  double stiffness = 0.0;              // k_n for linear and energy_conserving[_2005], N/m
  double characteristic_length = 0.0;  // d_c of energy_conserving[_2005], m (0: smaller diameter)
  double alpha = 0.2;                  // dashpot constant of hertz_sediment
  bool tsuji_dashpot = false;          // hertz_sediment: dashpot = "tsuji" (false: "constant", Eq. 14 as printed)
  double stiffness_ratio = 0.0;        // k_t/k_n for linear_coulomb (0: 2(1-nu)/(2-nu); 1 with HH)
  bool bound_whole_force = false;      // mindlin: friction_bound = "total" (false: "spring", as printed)
  // hooke_hysteresis only:
  double characteristic_velocity = 0;  // v_c, m/s
  double max_stiffness_ratio = 0;      // k2max/k_n, > 1
  double adhesion_stiffness_ratio = 0; // k_c/k_n
  double plasticity_depth = 0;         // phi_f
  bool no_tension = false;             // clamp F_n >= 0
  bool tangential_damping = true;      // gamma_t = gamma_n (false: 0)
};

// Effective moduli of two materials (spec notation): E* and G*.
double effective_modulus(const Material& a, const Material& b);
double effective_shear_modulus(const Material& a, const Material& b);

// Builds the law for materials a and b. Throws std::invalid_argument for combinations that
// the scenario validator should have refused.
PairLaw make_pair_law(const ContactSpec& spec, const Material& a, const Material& b);

// The table of laws indexed [a * n + b] for n materials.
struct LawTable {
  int n_materials = 0;
  std::vector<PairLaw> laws;
  const PairLaw& at(int a, int b) const { return laws[static_cast<std::size_t>(a * n_materials + b)]; }
  // True when all laws use the same pair of model types.
  bool uniform() const;
  // True when some law's normal model corrects positions (models P, F).
  bool corrects_positions() const;
  // The name of a normal model in the table that has no rates (block steps cannot run it),
  // or "" when every law has them.
  std::string without_rates() const;
};

}  // namespace tsubu
