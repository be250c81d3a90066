// The simulation box: bounds and periodic axes, with the minimum-image convention.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tsubu/core/dual.hpp"
#include "tsubu/core/vec3.hpp"

namespace tsubu {

// The names of the box's faces, numbered 2 axis + side (0 lower, 1 upper) as
// Domain::departed numbers them: the scenario's domain.open and outflow.csv's `face`.
inline constexpr std::array<std::string_view, 6> kBoxFaces = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};

struct Domain {
  Vec3 lower, upper;                 // m
  std::array<bool, 3> periodic{};    // per axis x, y, z
  // Open faces, per axis: [0] the lower face, [1] the upper. A grain whose centre crosses an
  // open face has left the run (sim/outflow.hpp); across any other non-periodic face it is
  // lost, and the run stops.
  std::array<std::array<bool, 2>, 3> open{};

  double length(int k) const { return upper[k] - lower[k]; }

  // Shortest vector from b to a under the periodic axes, for positions inside the box
  // (their difference is below one box length, so one shift is enough).
  Vec3 separation(const Vec3& a, const Vec3& b) const {
    Vec3 d = a - b;
    for (int k = 0; k < 3; ++k)
      if (periodic[k]) {
        const double L = length(k);
        if (d[k] > 0.5 * L) d[k] -= L;
        else if (d[k] < -0.5 * L) d[k] += L;
      }
    return d;
  }

  // Map a position back into the box along periodic axes.
  Vec3 wrap(Vec3 x) const {
    for (int k = 0; k < 3; ++k)
      if (periodic[k]) {
        x[k] -= length(k) * std::floor((x[k] - lower[k]) / length(k));
        if (x[k] >= upper[k]) x[k] = lower[k];  // round-off at the upper face
      }
    return x;
  }

  bool inside(const Vec3& x) const {
    for (int k = 0; k < 3; ++k)
      if (!periodic[k] && (x[k] < lower[k] || x[k] > upper[k])) return false;
    return true;
  }

  bool any_open() const {
    for (const auto& faces : open)
      if (faces[0] || faces[1]) return true;
    return false;
  }
  // The open face x has crossed, as 2 axis + side (0 lower, 1 upper; the first in x, y, z
  // order), or -1 for none.
  int departed(const Vec3& x) const {
    for (int k = 0; k < 3; ++k) {
      if (open[k][0] && x[k] < lower[k]) return 2 * k;
      if (open[k][1] && x[k] > upper[k]) return 2 * k + 1;
    }
    return -1;
  }
  // Inside the box, or gone through an open face: a position the run goes on with.
  bool kept(const Vec3& x) const { return inside(x) || departed(x) >= 0; }
};

// A stretch of prescribed wall motion: constant velocity until the time `until`.
struct WallMotion {
  double until = 0;  // s
  Vec3 velocity;     // m/s
};

// A stretch of a wall's surface motion, which moves no geometry: a velocity within a plane
// and a rotation (about a plane's normal, a cylinder's or cone's axis) until the time `until`.
struct SurfaceMotion {
  double until = 0;         // s
  Vec3 surface_velocity;    // m/s
  Vec3 angular_velocity;    // rad/s
};

// A unit vector perpendicular to the unit vector a.
inline Vec3 perpendicular(const Vec3& a) {
  int least = 0;  // the axis least aligned with a
  for (int k = 1; k < 3; ++k)
    if (std::abs(a[k]) < std::abs(a[least])) least = k;
  Vec3 e;
  e[least] = 1;
  const Vec3 u = cross(a, e);
  return u / norm(u);
}

// Where a particle's centre stands against a wall: its distance from the surface along the
// surface's normal at the nearest point (positive on the particles' side), and that unit
// normal, pointing towards the particles.
// Where a particle's centre is from a wall: the distance from the wall's nearest point and the
// unit normal from there towards the centre; on Dual (core/dual.hpp) with their rates, from
// the centre's position and velocity relative to the wall.
template <class T>
struct BasicWallTouch {
  T distance = 0;  // m
  Vector<T> normal;
};
using WallTouch = BasicWallTouch<double>;

enum class WallShape { plane, cylinder, cone, mesh };

class TriangleMesh;  // world/mesh.hpp

// A plane: infinite; `normal` is a unit vector pointing into the particles' side. A wall with
// a `motion` moves as a rigid plane: in each step with the velocity of the stretch that holds
// the step's midpoint (standing still after the last stretch). Its surface may move besides,
// within the plane, which moves no geometry (a conveyor belt, a turntable, a drum's end): a
// velocity in the plane and a rotation about the normal. The velocity of the surface where a
// particle touches it (surface_velocity_at) enters the relative velocity of the contact.
//
// A plane may have a circular hole about `point` (an outlet in a silo's floor, `hole_radius`
// > 0): over the hole the nearest point of the plate is on the hole's rim, and a grain
// touches the rim along the line from it to its centre.
//
// A cylinder: infinitely long, about the line through `point` along the unit vector `axis`,
// of `radius`, with the particles inside it or outside. Its surface may turn about its axis
// (a rotating drum: the rotation moves no geometry); with a `motion` it moves in a straight
// line as a plane does (`point`, and so the axis, advancing; a cone alike).
//
// A cone: the surface of a truncated cone (a hopper, a funnel, a pipe of finite length) about
// the same kind of axis, from the circle of `radius` about `point` to the circle of
// `end_radius` about point + length axis; its ends are open. A grain touches the face, on the
// particles' side (`inside`: the side of the axis), or either rim from any side (as a
// plane's hole rim). Its surface may turn about its axis.
//
// A mesh: triangles (world/mesh.hpp), each a partner of its own contacts (World::wall_elements);
// `point` is how far the mesh has moved from where the scenario put it, and it moves as a
// plane does, with `motion`. Its surface may move on its own, in the contact's plane (a
// conveyor of triangles, `surface_velocity`); or the mesh may turn besides, as a rigid body, at `angular_velocity` about
// the axis through point + axis_offset (a mixer's blade), constant or in `surface_motion`
// stretches about one axis, `turn_axis` (a drum spun up, a blade that stops or turns back): by
// the angle at the time t of the evaluation, known in closed form (turn_to; the integral of
// the stretches' angular velocities). Its triangles are kept as read; a
// position is taken into the mesh's frame to find where it touches (to_mesh), and the
// normal found back out (from_mesh). touch() is not defined for it: World::touch_element is.
struct Wall {
  Vec3 point;
  Vec3 normal;  // plane
  int material = 0;
  std::vector<WallMotion> motion;  // in time order; empty: a fixed wall
  Vec3 velocity;                   // m/s, during the current step
  Vec3 surface_velocity;           // m/s, in the plane, during the current step
  Vec3 angular_velocity;           // rad/s, along the normal or the axis, during the current step
  // The surface's motion in stretches, in time order (empty: the constant surface_velocity
  // and angular_velocity above); after the last one the surface stands still.
  std::vector<SurfaceMotion> surface_motion;
  Vec3 axis_offset;                // m, a point of the rotation's axis, from `point` (it moves with the wall)
  WallShape shape = WallShape::plane;
  Vec3 axis;           // cylinder, cone
  double radius = 0;   // m, cylinder; cone: at `point`
  bool inside = true;  // cylinder, cone: the particles are inside it
  double end_radius = 0;  // m, cone: at point + length axis
  double length = 0;      // m, cone: along the axis
  double hole_radius = 0;  // m, plane: a circular hole about `point` (0: none)
  std::shared_ptr<const TriangleMesh> mesh;  // mesh
  Vec3 turn_axis;                            // mesh: the unit axis it turns about (zero: it does not turn)
  double turn_cos = 1, turn_sin = 0;         // mesh: of the angle it has turned by

  // A plane's signed distance from x (positive on the particles' side).
  double distance(const Vec3& x) const { return dot(x - point, normal); }

  WallTouch touch(const Vec3& x) const { return touch_on<double>(x); }
  // The same on the number type T: on Dual, x carries the centre's velocity relative to the
  // wall's motion, and the touch the rates of the distance and the normal (exact: the same
  // expressions differentiated; the branches chosen by value).
  template <class T>
  BasicWallTouch<T> touch_on(const Vector<T>& x) const {
    using V = Vector<T>;
    if (shape == WallShape::plane) {
      const T d = dot(x - point, normal);
      if (hole_radius > 0) {
        const V along = (x - point) - d * normal;  // in the plane, from the hole's centre
        const T rho = norm(along);
        if (rho < hole_radius) {  // over the hole: the nearest point of the plate is on the rim
          const V out = rho > 0 ? along / rho : V(perpendicular(normal));
          const V from_rim = (x - point) - hole_radius * out;
          const T dist = norm(from_rim);
          return {dist, dist > 0 ? from_rim / dist : V(normal)};
        }
      }
      return {d, normal};
    }
    const V rel = x - point;
    const T s = dot(rel, axis);  // along the axis
    const V off = rel - s * axis;  // from the axis
    const T rho = norm(off);
    const V out = rho > 0 ? off / rho : V(perpendicular(axis));  // on the axis itself: any direction
    if (shape == WallShape::cylinder) return inside ? BasicWallTouch<T>{radius - rho, -out} : BasicWallTouch<T>{rho - radius, out};
    return cone_touch<T>(rel, s, rho, out);
  }
  // The cone's nearest point in the half-plane (s, rho) through the axis and x, where the
  // surface is the segment from (0, radius) to (length, end_radius): on the face, the signed
  // distance along the face's normal; beyond either end, the distance from that end's rim.
  template <class T>
  BasicWallTouch<T> cone_touch(const Vector<T>& rel, const T& s, const T& rho, const Vector<T>& out) const {
    const double rise = end_radius - radius, slant = std::hypot(length, rise);
    const T t = (s * length + (rho - radius) * rise) / (slant * slant);  // along the segment, 0 to 1
    if (t > 0 && t < 1) {
      const double across = rise / slant, towards_axis = -length / slant;  // the face's normal towards the axis
      return {(inside ? 1 : -1) * (s * across + (rho - radius) * towards_axis), cone_normal<T>(out)};
    }
    const Vector<T> from_rim = t <= 0 ? rel - radius * out : rel - length * axis - end_radius * out;
    const T dist = norm(from_rim);
    return {dist, dist > 0 ? from_rim / dist : (inside ? -out : out)};
  }

  // The normal of a cone's face, towards the particles, where `out` points from the axis.
  template <class T = double>
  Vector<T> cone_normal(const Vector<T>& out) const {
    const double rise = end_radius - radius, slant = std::hypot(length, rise);
    const Vector<T> towards_axis = (rise / slant) * axis - (length / slant) * out;
    return inside ? towards_axis : -towards_axis;
  }

  // A mesh turning at the constant angular velocity omega (zero: not at all).
  void turn_at(const Vec3& omega) {
    angular_velocity = omega;
    turn_axis = omega == Vec3{} ? Vec3{} : omega / norm(omega);
  }
  // A turning mesh's rotation of v by the angle it has turned (sign -1: back).
  Vec3 turned(const Vec3& v, double sign) const {
    if (turn_axis == Vec3{}) return v;
    const Vec3& k = turn_axis;
    const double s = sign * turn_sin;
    return turn_cos * v + s * cross(k, v) + (1 - turn_cos) * dot(k, v) * k;
  }
  // A position in a mesh's own frame (where its triangles were read and placed), and a
  // direction found there back in the box's.
  Vec3 to_mesh(const Vec3& x) const {
    const Vec3 axis_point = point + axis_offset;
    return turned(x - axis_point, -1) + axis_offset;
  }
  Vec3 from_mesh(const Vec3& direction) const { return turned(direction, 1); }
  // A turning mesh's angle at the time t, about turn_axis: |omega| t for a constant rotation;
  // in stretches, the sum of each one's angular velocity times its time up to t (none after
  // the last).
  void turn_to(double t) {
    if (!mesh) return;
    double angle = 0;
    if (surface_motion.empty()) {
      angle = norm(angular_velocity) * t;
    } else {
      double start = 0;
      for (const SurfaceMotion& m : surface_motion) {
        if (!(t > start)) break;
        angle += dot(m.angular_velocity, turn_axis) * (std::min(t, m.until) - start);
        start = m.until;
      }
    }
    turn_cos = std::cos(angle), turn_sin = std::sin(angle);
  }

  // A plane without a hole: its normal is the same wherever a particle touches it.
  bool whole_plane() const { return shape == WallShape::plane && !(hole_radius > 0); }

  bool surface_moves() const {
    return !surface_motion.empty() || !(surface_velocity == Vec3{}) || !(angular_velocity == Vec3{});
  }
  // The velocity of the surface at the nearest point to x, where x touches it (t = touch(x)).
  // On a plane's face the rotation is about the normal, so its part is the same at x itself,
  // which is used; on a hole's rim, a cylinder and a cone the nearest point is. A mesh's
  // surface velocity (a conveyor of triangles, on a mesh that does not turn) is taken in the
  // contact's plane, where the surface can move without moving the mesh: v_s - (v_s . n) n.
  Vec3 surface_velocity_at(const Vec3& x, const WallTouch& t) const {
    if (!surface_moves()) return velocity;
    if (mesh) {
      if (!(surface_velocity == Vec3{})) return velocity + (surface_velocity - dot(surface_velocity, t.normal) * t.normal);
      return velocity + cross(angular_velocity, x - t.distance * t.normal - (point + axis_offset));
    }
    const bool face = shape == WallShape::plane && t.normal == normal;
    const Vec3 at = face ? x : x - t.distance * t.normal;
    return velocity + surface_velocity + cross(angular_velocity, at - (point + axis_offset));
  }
  // (A mesh: of its surface's motion at x itself, the fastest a surface through x can move.)
  Vec3 surface_velocity_at(const Vec3& x) const { return surface_velocity_at(x, mesh ? WallTouch{} : touch(x)); }

  Vec3 velocity_at(double t) const {
    for (const WallMotion& m : motion)
      if (t < m.until) return m.velocity;
    return {};
  }
  // When the velocity or the surface's motion next changes after t (the end of the stretch
  // that holds t), s; infinite when neither changes again.
  double next_change(double t) const {
    double next = std::numeric_limits<double>::infinity();
    for (const WallMotion& m : motion)
      if (t < m.until) {
        next = m.until;
        break;
      }
    for (const SurfaceMotion& m : surface_motion)
      if (t < m.until) return std::min(next, m.until);
    return next;
  }
  // The largest speed of its motion, m/s.
  double top_speed() const {
    double v = 0;
    for (const WallMotion& m : motion) v = std::max(v, norm(m.velocity));
    return v;
  }
  // The largest rate of its surface's turning, rad/s, constant or over its stretches.
  double top_turning_rate() const {
    double w = norm(angular_velocity);
    for (const SurfaceMotion& m : surface_motion) w = std::max(w, norm(m.angular_velocity));
    return w;
  }

  // Moves the wall over the step [t, t + dt], and sets its velocity and its surface's motion
  // for the step: those of the stretches that hold its midpoint. The wall moves by each
  // stretch's velocity over its part of the step, so that it stays on its closed form when a
  // stretch ends inside the step (block steps' long intervals between block times far from
  // any grain do that); an end within round-off of the step's start or end counts as there.
  void advance(double t, double dt) {
    motion_during(t + 0.5 * dt);
    turn_to(t + dt);  // a turning mesh, where the evaluation at the step's end sees it
    if (motion.empty()) return;
    const double end = t + dt, slack = 1e-9 * dt;
    double from = t;
    for (const WallMotion& m : motion) {
      if (m.until <= from + slack) continue;
      if (m.until >= end - slack) break;
      point += m.velocity * (m.until - from);  // a stretch that ends inside the step
      from = m.until;
    }
    point += from == t ? velocity * dt : velocity_at(0.5 * (from + end)) * (end - from);
  }
  // The velocity and surface motion of the stretches that hold the time t.
  void motion_during(double t) {
    if (!motion.empty()) velocity = velocity_at(t);
    surface_during(t);
  }
  // The surface's motion of the stretch that holds the time t (standing still after the last).
  void surface_during(double t) {
    if (surface_motion.empty()) return;
    surface_velocity = angular_velocity = Vec3{};
    for (const SurfaceMotion& m : surface_motion)
      if (t < m.until) {
        surface_velocity = m.surface_velocity, angular_velocity = m.angular_velocity;
        break;
      }
  }
};

struct Material {
  std::string name;
  double density = 0;         // kg/m^3
  double youngs_modulus = 0;  // Pa
  double poisson = 0;         // -
};

}  // namespace tsubu
