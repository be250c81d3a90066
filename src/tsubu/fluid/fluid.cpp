#include "tsubu/fluid/fluid.hpp"

#include <algorithm>
#include <cmath>

#include "tsubu/core/dual.hpp"

namespace tsubu {

namespace {

using std::pow;
using std::sqrt;
using std::tanh;

// eta(Re) on the points of the table: piecewise linear, constant outside.
template <class T>
T interpolate(const std::vector<double>& xs, const std::vector<double>& ys, T x) {
  if (xs.empty()) return T(0.0);
  if (value(x) <= xs.front()) return T(ys.front());
  if (value(x) >= xs.back()) return T(ys.back());
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), value(x)) - xs.begin());
  const double slope = (ys[k] - ys[k - 1]) / (xs[k] - xs[k - 1]);
  return T(ys[k - 1]) + T(slope) * (x - T(xs[k - 1]));
}

// Re C_D(Re): finite at Re = 0 (24), so the drag 1/2 rho S C_D |u| u = 1/2 rho S (nu/d) (Re C_D) u
// is smooth through u = 0.
template <class T>
T re_times_cd(T re) {
  if (value(re) <= Fluid::drag_cap_re) return T(24.0) + T(3.6) * pow(re, 0.687);
  return T(0.44) * re;
}

template <class T>
T loth(T re, T rr) {
  return rr * (T(1.0) - (T(0.675) + T(0.15) * (T(1.0) + tanh(T(0.28) * (rr - T(2.0))))) * tanh(T(0.18) * sqrt(re)));
}

template <class T>
struct Load {
  Vector<T> force, torque;
};

// The fluid's force (buoyancy, drag, lift) and torque, on double (values) or Dual (rates).
template <class T>
Load<T> load(const Fluid& f, double d, const Vec3& g, const Vector<T>& u, const Vector<T>& w) {
  Load<T> out{{T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  if (!f.enabled) return out;
  const double area = M_PI * d * d / 4, volume = M_PI * d * d * d / 6;
  if (f.buoyancy) {
    const double b = -f.density * volume;
    out.force = {T(b * g.x), T(b * g.y), T(b * g.z)};
  }
  if (f.stokes_torque) out.torque = T(-M_PI * f.density * f.viscosity * d * d * d) * w;
  const bool spin = f.lift != SpinModel::none;
  if (!f.drag && !spin) return out;

  const T q2 = dot(u, u);
  const double half_rho_s = 0.5 * f.density * area;
  if (value(q2) == 0) {
    // At rest relative to the fluid: the Stokes limit of the drag, no lift.
    if (f.drag) out.force = out.force + T(-half_rho_s * f.viscosity / d * 24.0) * u;
    return out;
  }
  const T q = sqrt(q2);
  const T re = q * T(d / f.viscosity);
  const T s2 = dot(w, w);
  const bool spinning = value(s2) > 0;
  const T s = spinning ? sqrt(s2) : T(0.0);

  T correction(1.0);   // C_D(Re, W)/C_D(Re, 0)
  T lift_coefficient(0.0);
  if (f.lift == SpinModel::kurose_komori && spinning) {
    T star = T(0.5 * d) * s / q;          // Omega*
    if (value(star) > 0.5) star = T(0.5);  // held at its value at 0.5 beyond
    const T e1 = interpolate(f.eta.re, f.eta.eta1, re);
    const T e2 = interpolate(f.eta.re, f.eta.eta2, re);
    const T e3 = interpolate(f.eta.re, f.eta.eta3, re);
    const T star2 = star * star;
    correction = T(1.0) + e1 * sqrt(star) + e2 * star2 * star2;
    lift_coefficient = e3 * star;
  } else if (f.lift == SpinModel::loth && spinning) {
    lift_coefficient = loth(re, T(d) * s / q);
  }
  if (f.drag)
    out.force = out.force + (T(-half_rho_s * f.viscosity / d) * re_times_cd(re) * correction) * u;
  if (value(lift_coefficient) != 0) {
    const Vector<T> c = cross(w, u);
    const T c2 = dot(c, c);
    if (value(c2) > 0) out.force = out.force + (T(half_rho_s) * lift_coefficient * q2 / sqrt(c2)) * c;
  }
  return out;
}

}  // namespace

double Fluid::added_mass_of(double diameter) const {
  if (!enabled || !added_mass) return 0;
  return added_mass_coefficient * density * M_PI * diameter * diameter * diameter / 6;
}

FluidLoad fluid_load(const Fluid& fluid, double d, const Vec3& g, const Vec3& u, const Vec3& omega) {
  const Load<double> l = load<double>(fluid, d, g, u, omega);
  return {l.force, l.torque};
}

FluidLoad fluid_load_rate(const Fluid& fluid, double d, const Vec3& u, const Vec3& a, const Vec3& omega,
                          const Vec3& alpha) {
  return fluid_load_with_rate(fluid, d, {}, u, a, omega, alpha).rate;
}

FluidLoadWithRate fluid_load_with_rate(const Fluid& fluid, double d, const Vec3& g, const Vec3& u, const Vec3& a,
                                       const Vec3& omega, const Vec3& alpha) {
  const Load<Dual> l = load<Dual>(fluid, d, g, DualVec3(u, a), DualVec3(omega, alpha));
  return {{value(l.force), value(l.torque)}, {rate(l.force), rate(l.torque)}};
}

double drag_relaxation_time(const Fluid& fluid, double d, double m, double speed) {
  if (!fluid.enabled || !fluid.drag) return INFINITY;
  const double area = M_PI * d * d / 4;
  return m / (0.5 * fluid.density * area * fluid.viscosity / d * re_times_cd(speed * d / fluid.viscosity));
}

double drag_coefficient(double re) { return re_times_cd(re) / re; }

double loth_lift_coefficient(double re, double rr) { return loth(re, rr); }

double eta_at(const std::vector<double>& re_points, const std::vector<double>& values, double re) {
  return interpolate(re_points, values, re);
}

double rubey_speed(double rho_particle, double rho_fluid, double viscosity, double d, double g) {
  const double s1 = rho_particle / rho_fluid - 1;
  const double dstar = s1 * g * d * d * d / (viscosity * viscosity);
  return std::sqrt(s1 * g * d) * (std::sqrt(2.0 / 3.0 + 36.0 / dstar) - std::sqrt(36.0 / dstar));
}

}  // namespace tsubu
