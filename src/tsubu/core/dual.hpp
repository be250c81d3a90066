// Numbers that carry their time derivative (forward-mode differentiation): evaluating an
// expression on Duals gives its value and its exact rate, the chain rule applied per
// operation. The contact laws and the fluid forces are written once, as templates on the
// number type; run on double they give forces, run on Dual they also give the rates (jerks)
// that the Hermite integrator needs, so force and rate can never disagree.
#pragma once
#include <cmath>

#include "tsubu/core/vec3.hpp"

namespace tsubu {

struct Dual {
  double v = 0, d = 0;  // value and its time derivative
  constexpr Dual() = default;
  constexpr Dual(double value, double rate = 0) : v(value), d(rate) {}
};

constexpr Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.d + b.d}; }
constexpr Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.d - b.d}; }
constexpr Dual operator-(Dual a) { return {-a.v, -a.d}; }
constexpr Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
constexpr Dual operator/(Dual a, Dual b) { return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)}; }
constexpr Dual& operator+=(Dual& a, Dual b) { return a = a + b; }
constexpr Dual& operator-=(Dual& a, Dual b) { return a = a - b; }
constexpr Dual& operator*=(Dual& a, Dual b) { return a = a * b; }
// Branches of a law are chosen by value, as on double.
constexpr bool operator<(Dual a, Dual b) { return a.v < b.v; }
constexpr bool operator>(Dual a, Dual b) { return a.v > b.v; }
constexpr bool operator<=(Dual a, Dual b) { return a.v <= b.v; }
constexpr bool operator>=(Dual a, Dual b) { return a.v >= b.v; }
inline Dual sqrt(Dual a) {
  const double s = std::sqrt(a.v);
  return {s, a.d == 0 ? 0.0 : 0.5 * a.d / s};  // a constant zero stays a constant
}
inline Dual pow(Dual a, double p) {
  const double r = std::pow(a.v, p - 1);
  return {r * a.v, p * r * a.d};
}
inline Dual tanh(Dual a) {
  const double t = std::tanh(a.v);
  return {t, (1 - t * t) * a.d};
}
inline Dual abs(Dual a) { return a.v < 0 ? -a : a; }

constexpr double value(double x) { return x; }
constexpr double value(Dual x) { return x.v; }

// A three-vector of Duals: a vector and its rate.
struct DualVec3 {
  Dual x, y, z;
  constexpr DualVec3() = default;
  constexpr DualVec3(Dual a, Dual b, Dual c) : x(a), y(b), z(c) {}
  constexpr DualVec3(const Vec3& value, const Vec3& rate = {})
      : x(value.x, rate.x), y(value.y, rate.y), z(value.z, rate.z) {}
  constexpr DualVec3& operator+=(const DualVec3& o) { x += o.x, y += o.y, z += o.z; return *this; }
  constexpr DualVec3& operator-=(const DualVec3& o) { x -= o.x, y -= o.y, z -= o.z; return *this; }
  constexpr DualVec3& operator*=(Dual s) { x *= s, y *= s, z *= s; return *this; }
};

constexpr DualVec3 operator+(DualVec3 a, const DualVec3& b) { return a += b; }
constexpr DualVec3 operator-(DualVec3 a, const DualVec3& b) { return a -= b; }
constexpr DualVec3 operator-(const DualVec3& a) { return {-a.x, -a.y, -a.z}; }
constexpr DualVec3 operator*(DualVec3 a, Dual s) { return a *= s; }
constexpr DualVec3 operator*(Dual s, DualVec3 a) { return a *= s; }
constexpr DualVec3 operator*(DualVec3 a, double s) { return a *= Dual(s); }
constexpr DualVec3 operator*(double s, DualVec3 a) { return a *= Dual(s); }
constexpr DualVec3 operator/(const DualVec3& a, Dual s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr Dual dot(const DualVec3& a, const DualVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr DualVec3 cross(const DualVec3& a, const DualVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr Dual norm2(const DualVec3& a) { return dot(a, a); }
inline Dual norm(const DualVec3& a) { return sqrt(dot(a, a)); }

constexpr Vec3 value(const Vec3& a) { return a; }
constexpr Vec3 value(const DualVec3& a) { return {a.x.v, a.y.v, a.z.v}; }
constexpr Vec3 rate(const DualVec3& a) { return {a.x.d, a.y.d, a.z.d}; }

// The vector type that goes with a number type.
template <class T>
struct VectorOf;
template <>
struct VectorOf<double> {
  using type = Vec3;
};
template <>
struct VectorOf<Dual> {
  using type = DualVec3;
};
template <class T>
using Vector = typename VectorOf<T>::type;

}  // namespace tsubu
