// Forces and torques of a still fluid on a sphere (the fluid is at rest everywhere), their
// exact time derivatives for higher-order integrators, and Rubey's settling speed.
// Definitions: docs/engine.md, "Fluid forces"; keys: docs/scenario.md, [fluid].
#pragma once
#include <cmath>
#include <vector>

#include "tsubu/core/vec3.hpp"

namespace tsubu {

// How a spinning sphere's drag and lift are modelled.
enum class SpinModel {
  none,           // no lift, no drag correction
  kurose_komori,  // C_D (1 + eta1 W^0.5 + eta2 W^4), C_L = eta3 W, W = Omega* held at 0.5
  loth            // Loth (2008) spin lift, no drag correction
};

// eta1..eta3 of the Kurose-Komori correction as functions of Re: piecewise linear between
// the points, held constant outside them. Empty: all zero (no correction).
struct EtaTable {
  std::vector<double> re, eta1, eta2, eta3;
};

struct Fluid {
  bool enabled = false;     // false: no fluid at all (every force and the added mass are zero)
  double density = 0;       // kg/m^3
  double viscosity = 0;     // m^2/s, kinematic
  bool buoyancy = true;     // -rho_f V g
  bool drag = true;         // Schiller-Naumann (Sota & Watanabe Eq. 5)
  bool drag_cap = true;     // C_D = 0.44 above Re = 1000 (Clift et al.); false: Eq. 5 at every Re
  bool added_mass = true;   // extra translational inertia C_M rho_f V
  bool stokes_torque = true;  // -pi rho_f nu d^3 omega
  SpinModel lift = SpinModel::none;
  EtaTable eta;  // used by SpinModel::kurose_komori
  // Hindered settling (Richardson-Zaki): the drag of a grain whose surroundings hold solid
  // fraction phi is the lone grain's drag at the velocity u/(1-phi)^n, n the grain's
  // Richardson-Zaki exponent; phi is measured in a ball of hindered_ball_ratio grain radii
  // around the grain, the grain itself left out (fluid/crowding.hpp).
  bool hindered = false;
  double hindered_ball_ratio = 3;

  static constexpr double added_mass_coefficient = 0.5;  // C_M of a sphere in still fluid
  static constexpr double drag_cap_re = 1000;            // Re above which C_D = 0.44 (drag_cap)

  // The Re above which the drag coefficient is held at 0.44: drag_cap_re, or none.
  double cap_re() const { return drag_cap ? drag_cap_re : INFINITY; }

  // C_M rho_f V of a sphere of this diameter (0 without fluid or without added mass), kg.
  double added_mass_of(double diameter) const;
};

// What hindered settling needs of one grain: the solid fraction phi of its surroundings, the
// rate of phi, and the grain's Richardson-Zaki exponent n. The default (n = 0) is a lone
// grain: no correction.
struct Crowding {
  double solid_fraction = 0;  // phi
  double rate = 0;            // dphi/dt, 1/s
  double exponent = 0;        // n
};

// Force (buoyancy + drag + lift) and torque of the fluid on one sphere.
struct FluidLoad {
  Vec3 force, torque;
};

// The fluid's force and torque on a sphere of diameter d moving with velocity u and spin
// omega through the still fluid, under gravity g. Gravity itself (m g) is not included.
// With `crowd` the drag is hindered (Fluid::hindered).
FluidLoad fluid_load(const Fluid& fluid, double d, const Vec3& g, const Vec3& u, const Vec3& omega,
                     const Crowding& crowd = {});

// fluid_load of n grains at once, the same bits: out[k] = fluid_load(fluid, d[k], g, u[k],
// omega[k], crowd[k]). Without lift the grains go through each expression together (no call
// per grain, the drag's power laws back to back): half the cost of one grain at a time
// (docs/performance.md). The fixed-step evaluation calls it for every grain at every step.
void fluid_loads(const Fluid& fluid, const Vec3& g, std::size_t n, const double* d, const Vec3* u, const Vec3* omega,
                 const Crowding* crowd, FluidLoad* out);

// d/dt of fluid_load along a trajectory with du/dt = a and domega/dt = alpha (the jerk of
// the fluid force and the rate of its torque). Exact derivatives of the same expressions
// (forward-mode differentiation), so force and rate never disagree. At u = 0 the drag rate
// is the limit -f(0) a; at omega = 0 exactly the spin terms' rates are taken as zero (the
// Kurose-Komori W^0.5 term has an unbounded rate there).
// With `crowd`, its rate enters the hindered drag's rate.
FluidLoad fluid_load_rate(const Fluid& fluid, double d, const Vec3& u, const Vec3& a, const Vec3& omega,
                          const Vec3& alpha, const Crowding& crowd = {});

// How the load changes with the grain's velocity and spin about those it was evaluated at,
// where that change is exactly linear in the spin and smooth in the velocity: drag and the
// Stokes torque, no lift (`exact` is false with a lift model, whose change is not given).
// The drag is -K(q) u (q = |u|), so its derivative along a velocity change du is
// -(K du + K_q (e.du) e) with e = u/q and K_q = q dK/dq; the torque's is -c domega.
struct FluidSlope {
  bool exact = false;
  double drag = 0;        // K, kg/s
  double drag_speed = 0;  // K_q = q dK/dq, kg/s (0 at rest, where Re dC_D/dRe Re vanishes)
  double speed = 0;       // q, m/s
  Vec3 direction;         // e
  double spin_drag = 0;   // c, kg m^2/s
  Vec3 force_change(const Vec3& du) const { return -(drag * du + drag_speed * dot(direction, du) * direction); }
  Vec3 torque_change(const Vec3& domega) const { return -spin_drag * domega; }
  // The drag relaxation time (drag_relaxation_time) of translational mass m at speed
  // `at_speed`, from K moved along its slope to that speed.
  double relaxation_time(double m, double at_speed) const;
};

// Both at once (one evaluation on Duals; the values agree with fluid_load to round-off), and,
// when `slope` is given, the load's slope about u and omega.
struct FluidLoadWithRate {
  FluidLoad value, rate;
};
FluidLoadWithRate fluid_load_with_rate(const Fluid& fluid, double d, const Vec3& g, const Vec3& u, const Vec3& a,
                                       const Vec3& omega, const Vec3& alpha, const Crowding& crowd = {},
                                       FluidSlope* slope = nullptr);

// Relaxation time of the drag on a sphere of diameter d and translational mass m moving at
// `speed` through the still fluid: m / (F_drag/speed), s (infinite without drag); hindered
// by `crowd`.
double drag_relaxation_time(const Fluid& fluid, double d, double m, double speed, const Crowding& crowd = {});

// The factor (1 - phi)^-n by which hindered settling scales the velocity the drag is taken at
// (1 for a lone grain).
double hindrance(const Crowding& crowd);

// Terminal settling speed of a sphere of density rho_particle and diameter d alone in the
// still fluid (buoyancy and drag with Schiller-Naumann balance its weight), m/s; 0 for a grain
// not denser than the fluid. g is the magnitude of gravity.
double terminal_speed(const Fluid& fluid, double rho_particle, double d, double g);

// Richardson and Zaki's (1954) exponent n of u = u_t (1 - phi)^n for spheres far from the
// walls, from the lone grain's terminal Reynolds number: 4.65 below Re_t = 0.2,
// 4.4 Re_t^-0.03 up to 1, 4.4 Re_t^-0.1 up to 500, 2.39 above.
double richardson_zaki_exponent(double re_terminal);

// Schiller-Naumann C_D(Re) = 24/Re (1 + 0.15 Re^0.687) for Re <= 1000, 0.44 above.
double drag_coefficient(double re, bool capped = true);

// Loth (2008) spin lift coefficient for the spin ratio rr = d|omega|/|u|.
double loth_lift_coefficient(double re, double rr);

// Value of an eta table column at re (piecewise linear, constant outside the points).
double eta_at(const std::vector<double>& re_points, const std::vector<double>& values, double re);

// Rubey (1933) settling speed of a natural grain, m/s:
//   u / sqrt((s-1) g d) = sqrt(2/3 + 36/d*) - sqrt(36/d*),  d* = (s-1) g d^3 / nu^2,  s = rho_p/rho_f.
// g is the magnitude of gravity.
double rubey_speed(double rho_particle, double rho_fluid, double viscosity, double d, double g);

}  // namespace tsubu
