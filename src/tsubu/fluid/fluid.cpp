#include "tsubu/fluid/fluid.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

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

constexpr double kSchillerNaumannExponent = 0.687;  // Re C_D = 24 + 3.6 Re^0.687 (Eq. 5)

// Re C_D(Re): finite at Re = 0 (24), so the drag 1/2 rho S C_D |u| u = 1/2 rho S (nu/d) (Re C_D) u
// is smooth through u = 0. Schiller-Naumann up to cap_re (Fluid::cap_re), 0.44 above.
template <class T>
T re_times_cd(T re, double cap_re) {
  if (value(re) <= cap_re) return T(24.0) + T(3.6) * pow(re, kSchillerNaumannExponent);
  return T(0.44) * re;
}

// Re d(Re C_D)/dRe, from Re C_D = rc at re: 0.687 (rc - 24) on Schiller-Naumann, rc above the cap.
double re_times_cd_slope(double rc, double re, double cap_re) {
  return re <= cap_re ? kSchillerNaumannExponent * (rc - 24.0) : rc;
}

template <class T>
T loth(T re, T rr) {
  return rr * (T(1.0) - (T(0.675) + T(0.15) * (T(1.0) + tanh(T(0.28) * (rr - T(2.0))))) * tanh(T(0.18) * sqrt(re)));
}

template <class T>
struct Load {
  Vector<T> force, torque;
};

// (1 - phi)^-n with the rate of phi, on double (values) or Dual (rates).
template <class T>
T hindrance_of(const Crowding& c) {
  if (c.solid_fraction == 0) return T(1.0);  // alone: phi and its rate are 0
  const double s = std::pow(1 - c.solid_fraction, -c.exponent);
  if constexpr (std::is_same_v<T, double>) return s;
  else return T(s, c.exponent * s / (1 - c.solid_fraction) * c.rate);  // d/dt (1-phi)^-n = n (1-phi)^(-n-1) dphi/dt
}

bool hindered(const Fluid& f, const Crowding& c) { return f.hindered && c.exponent != 0; }

// The fluid's force (buoyancy, drag, lift) and torque, on double (values) or Dual (rates).
// Hindered settling (Fluid::hindered): the drag is the lone grain's at the velocity s u,
// s = (1 - phi)^-n, so a grain in a homogeneous suspension settles at u_t (1 - phi)^n.
// With `slope`, also the load's slope about u and omega (FluidSlope), from the values.
template <class T>
Load<T> load(const Fluid& f, double d, const Vec3& g, const Vector<T>& u, const Vector<T>& w, const Crowding& crowd,
             FluidSlope* slope = nullptr) {
  Load<T> out{{T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  const bool spin_model = f.lift != SpinModel::none;
  if (slope) {
    *slope = FluidSlope{};
    slope->exact = !spin_model;
  }
  if (!f.enabled) return out;
  const double area = M_PI * d * d / 4, volume = M_PI * d * d * d / 6;
  if (f.buoyancy) {
    const double b = -f.density * volume;
    out.force = {T(b * g.x), T(b * g.y), T(b * g.z)};
  }
  if (f.stokes_torque) {
    const double c = M_PI * f.density * f.viscosity * d * d * d;
    out.torque = T(-c) * w;
    if (slope) slope->spin_drag = c;
  }
  if (!f.drag && !spin_model) return out;

  const T q2 = dot(u, u);
  const double half_rho_s = 0.5 * f.density * area;
  const bool hinder = f.drag && hindered(f, crowd);
  const T s = hinder ? hindrance_of<T>(crowd) : T(1.0);
  if (value(q2) == 0) {
    // At rest relative to the fluid: the Stokes limit of the drag, no lift.
    if (f.drag) {
      T stokes(-half_rho_s * f.viscosity / d * 24.0);
      if (hinder) stokes = stokes * s;
      out.force = out.force + stokes * u;
      if (slope) slope->drag = -value(stokes);
    }
    return out;
  }
  const T q = sqrt(q2);
  const T re = q * T(d / f.viscosity);
  const T w2 = dot(w, w);
  const bool spinning = value(w2) > 0;
  const T spin = spinning ? sqrt(w2) : T(0.0);

  T correction(1.0);   // C_D(Re, W)/C_D(Re, 0)
  T lift_coefficient(0.0);
  if (f.lift == SpinModel::kurose_komori && spinning) {
    T star = T(0.5 * d) * spin / q;       // Omega*
    if (value(star) > 0.5) star = T(0.5);  // held at its value at 0.5 beyond
    const T e1 = interpolate(f.eta.re, f.eta.eta1, re);
    const T e2 = interpolate(f.eta.re, f.eta.eta2, re);
    const T e3 = interpolate(f.eta.re, f.eta.eta3, re);
    const T star2 = star * star;
    correction = T(1.0) + e1 * sqrt(star) + e2 * star2 * star2;
    lift_coefficient = e3 * star;
  } else if (f.lift == SpinModel::loth && spinning) {
    lift_coefficient = loth(re, T(d) * spin / q);
  }
  if (f.drag) {
    const T re_drag = hinder ? re * s : re;
    const T rc = re_times_cd(re_drag, f.cap_re());
    const T k = T(half_rho_s * f.viscosity / d) * rc * correction * s;  // the drag is -k u
    out.force = out.force - k * u;
    if (slope) {
      const double c = value(k) / value(rc);
      slope->drag = value(k);
      slope->drag_speed = c * re_times_cd_slope(value(rc), value(re_drag), f.cap_re());
      slope->speed = value(q);
      slope->direction = value(u) / value(q);
    }
  }
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

FluidLoad fluid_load(const Fluid& fluid, double d, const Vec3& g, const Vec3& u, const Vec3& omega,
                     const Crowding& crowd) {
  const Load<double> l = load<double>(fluid, d, g, u, omega, crowd);
  return {l.force, l.torque};
}

namespace {

// fluid_loads for at most kBatch grains: load<double>'s expressions in the same order (the
// same bits), in three passes over the grains (the power law alone in the second). Drag on,
// no lift: the drag is -K u with K = (1/2 rho_f S nu/d) (Re C_D)(s Re) s, s the hindrance (1
// for a lone grain: the products with it are exact); at u = 0 that is load()'s Stokes limit
// to the bit (Re = 0: Re C_D = 24).
constexpr std::size_t kBatch = 64;

void drag_loads(const Fluid& f, const Vec3& g, std::size_t n, const double* d, const Vec3* u, const Vec3* omega,
                const Crowding* crowd, FluidLoad* out) {
  double re[kBatch], coefficient[kBatch], s[kBatch], rc[kBatch];
  for (std::size_t k = 0; k < n; ++k) s[k] = 1.0;
  if (f.hindered)
    for (std::size_t k = 0; k < n; ++k)
      if (hindered(f, crowd[k])) s[k] = hindrance_of<double>(crowd[k]);
  for (std::size_t k = 0; k < n; ++k) {
    const double dk = d[k];
    const double area = M_PI * dk * dk / 4, volume = M_PI * dk * dk * dk / 6;
    Vec3 force, torque;
    if (f.buoyancy) {
      const double b = -f.density * volume;
      force = {b * g.x, b * g.y, b * g.z};
    }
    if (f.stokes_torque) torque = -(M_PI * f.density * f.viscosity * dk * dk * dk) * omega[k];
    out[k] = {force, torque};
    const double half_rho_s = 0.5 * f.density * area;
    re[k] = sqrt(dot(u[k], u[k])) * (dk / f.viscosity) * s[k];
    coefficient[k] = half_rho_s * f.viscosity / dk;
  }
  const double cap = f.cap_re();
  for (std::size_t k = 0; k < n; ++k) rc[k] = re_times_cd(re[k], cap);
  for (std::size_t k = 0; k < n; ++k) out[k].force = out[k].force - (coefficient[k] * rc[k] * s[k]) * u[k];
}

}  // namespace

void fluid_loads(const Fluid& fluid, const Vec3& g, std::size_t n, const double* d, const Vec3* u, const Vec3* omega,
                 const Crowding* crowd, FluidLoad* out) {
  if (fluid.enabled && fluid.drag && fluid.lift == SpinModel::none) {
    for (std::size_t first = 0; first < n; first += kBatch)
      drag_loads(fluid, g, std::min(kBatch, n - first), d + first, u + first, omega + first, crowd + first, out + first);
    return;
  }
  for (std::size_t k = 0; k < n; ++k) out[k] = fluid_load(fluid, d[k], g, u[k], omega[k], crowd[k]);
}

FluidLoad fluid_load_rate(const Fluid& fluid, double d, const Vec3& u, const Vec3& a, const Vec3& omega,
                          const Vec3& alpha, const Crowding& crowd) {
  return fluid_load_with_rate(fluid, d, {}, u, a, omega, alpha, crowd).rate;
}

FluidLoadWithRate fluid_load_with_rate(const Fluid& fluid, double d, const Vec3& g, const Vec3& u, const Vec3& a,
                                       const Vec3& omega, const Vec3& alpha, const Crowding& crowd, FluidSlope* slope) {
  const Load<Dual> l = load<Dual>(fluid, d, g, DualVec3(u, a), DualVec3(omega, alpha), crowd, slope);
  return {{value(l.force), value(l.torque)}, {rate(l.force), rate(l.torque)}};
}

double drag_relaxation_time(const Fluid& fluid, double d, double m, double speed, const Crowding& crowd) {
  if (!fluid.enabled || !fluid.drag) return INFINITY;
  const double area = M_PI * d * d / 4;
  const double s = hindrance(fluid.hindered ? crowd : Crowding{});
  return m / (0.5 * fluid.density * area * fluid.viscosity / d * re_times_cd(s * speed * d / fluid.viscosity, fluid.cap_re()) * s);
}

double FluidSlope::relaxation_time(double m, double at_speed) const {
  const double k = speed > 0 ? drag + drag_speed * (at_speed - speed) / speed : drag;
  return k > 0 ? m / k : INFINITY;
}

double hindrance(const Crowding& crowd) { return crowd.exponent == 0 ? 1.0 : hindrance_of<double>(crowd); }

double terminal_speed(const Fluid& fluid, double rho_particle, double d, double g) {
  // Weight net of buoyancy = drag: Re (Re C_D) = 4 Ar/3, Ar = (rho_p/rho_f - 1) g d^3/nu^2.
  const double ar = (rho_particle / fluid.density - 1) * g * d * d * d / (fluid.viscosity * fluid.viscosity);
  if (!(ar > 0)) return 0;
  const double k = 4 * ar / 3, cap = fluid.cap_re();
  double re;
  if (k >= cap * cap * 0.44) re = std::sqrt(k / 0.44);
  else if (k >= cap * re_times_cd(cap, cap)) re = cap;  // in the 0.5 % step of C_D at the cap
  else {
    // Newton from the Stokes root, which lies above the root of this convex increasing
    // function: the iterates fall monotonically onto it.
    re = std::min(k / 24, cap);
    for (int it = 0; it < 100; ++it) {
      const double f = re * re_times_cd(re, cap) - k, slope = 24 + 3.6 * 1.687 * std::pow(re, 0.687);
      const double next = re - f / slope;
      if (!(next < re)) break;
      re = next;
    }
  }
  return re * fluid.viscosity / d;
}

double richardson_zaki_exponent(double re) {
  if (re < 0.2) return 4.65;
  if (re < 1) return 4.4 * std::pow(re, -0.03);
  if (re < 500) return 4.4 * std::pow(re, -0.1);
  return 2.39;
}

double drag_coefficient(double re, bool capped) {
  Fluid f;
  f.drag_cap = capped;
  return re_times_cd(re, f.cap_re()) / re;
}

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
