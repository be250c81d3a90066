// Scenario loading: TOML -> checked plain structs. Keys are documented in docs/scenario.md;
// keep the two in step.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/core/format.hpp"
#include "tsubu/core/hash.hpp"
#include "tsubu/io/mesh_file.hpp"
#include "tsubu/world/mesh.hpp"
#include "tsubu/scenario/law_keys.hpp"
#include "tsubu/scenario/reader.hpp"
#include "tsubu/scenario/result_names.hpp"
#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

namespace {

// A scenario is a few KiB; the cap ends the read of an endless source (/dev/zero, a pipe)
// with an error instead of exhausting memory.
constexpr std::size_t kMaxScenarioBytes = 16 << 20;
constexpr std::int64_t kMaxSubdomains = 1 << 16;  // along one axis: far beyond any machine

std::string read_text(const std::string& path) {
  if (std::filesystem::is_directory(path)) throw InputError(path, 0, "", "is a folder; give the scenario file (TOML)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the scenario file");
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxScenarioBytes) throw InputError(path, 0, "", "is larger than 16 MiB: not a scenario file (TOML)");
  }
  return text;
}

// The end of the message for a --set value that is not TOML: a bare word (a letter first,
// e.g. block_hermite) was most likely meant as a string, which TOML writes in quotes, and
// the shell needs single quotes around it to keep them.
std::string quoting_hint(const std::string& path, const std::string& value) {
  if (value.empty() || !std::isalpha(static_cast<unsigned char>(value.front()))) return "";
  return "; a string value needs quotes: --set '" + path + "=\"" + value + "\"'";
}

// --set key.path=value: the value is TOML ("0.5", "\"hertz_tsuji\"", "[0,0,-9.81]"); a
// numeric path element selects an entry of an array of tables ("particles.0.file").
void apply_override(toml::table& root, const std::string& text) {
  const std::string origin = "--set " + text;
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError(origin, 1, "", "expected key.path=value");
  const std::string path = text.substr(0, eq), value = text.substr(eq + 1);
  // One value on one line: a line break would let the text add keys of its own.
  if (value.find_first_of("\r\n") != std::string::npos)
    throw InputError(origin, 1, path, "the value must be on one line (one TOML value, no line break)");
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  // The value, under the keys parts[from..] that the scenario lacks, parsed from the --set
  // text itself: every node made here names the --set as its source in errors.
  auto parse_under = [&](std::size_t from) {
    std::string keys;
    for (std::size_t k = from; k < parts.size(); ++k) {
      keys += k > from ? ".\"" : "\"";
      for (char c : parts[k]) keys += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
      keys += '"';
    }
    try {
      return toml::parse(keys + " = " + value, origin);
    } catch (const toml::parse_error& e) {
      throw InputError(origin, 1, path, "the value is not valid TOML: " + std::string(e.description()) + quoting_hint(path, value));
    }
  };
  toml::node* node = &root;
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    if (auto* t = node->as_table()) {
      if (!t->contains(parts[k])) {
        toml::table parsed = parse_under(k);
        t->insert(parts[k], std::move(*parsed.get(parts[k])));
        return;
      }
      node = t->get(parts[k]);
    } else if (auto* a = node->as_array()) {
      if (parts[k].empty() || parts[k].find_first_not_of("0123456789") != std::string::npos)
        throw InputError(origin, 1, path, "'" + parts[k] + "' must be an entry number (0, 1, ...) of this array of tables");
      const std::size_t idx = static_cast<std::size_t>(std::strtoul(parts[k].c_str(), nullptr, 10));
      if (idx >= a->size()) throw InputError(origin, 1, path, "no entry " + parts[k] + " in this array (it has " + std::to_string(a->size()) + ")");
      node = a->get(idx);
    } else {
      throw InputError(origin, 1, path, "'" + parts[k] + "' is not a table or array");
    }
  }
  auto* t = node->as_table();
  if (!t) throw InputError(origin, 1, path, "the parent of the last key is not a table");
  toml::table parsed = parse_under(parts.size() - 1);
  // Moved, not copied: a copied node forgets its source, which errors use to name the --set.
  t->insert_or_assign(parts.back(), std::move(*parsed.get(parts.back())));
}

std::string num(double v) { return format_number(v); }

// ", got <v>": the end of a message about a value out of its allowed range.
std::string got(double v) { return ", got " + num(v); }

int material_named(const Scenario& sc, const Section& s, std::string_view key, const std::string& name) {
  std::string names;
  for (std::size_t k = 0; k < sc.materials.size(); ++k) {
    if (sc.materials[k].name == name) return static_cast<int>(k);
    names += (names.empty() ? "" : ", ") + sc.materials[k].name;
  }
  s.fail(key, "unknown material \"" + name + "\"; defined in [[materials]]: " + (names.empty() ? "none" : names));
}

int material_index(const Scenario& sc, Section& s, std::string_view key) { return material_named(sc, s, key, s.text(key)); }

// [simulation.block_steps]: the step rules of the block-step Hermite integrator
// (docs/scenario.md, docs/integrators.md).
void read_block_steps(Section& s, BlockStepRules& r) {
  const std::int64_t levels = s.integer("levels", r.levels);
  if (levels < 0 || levels > 30) s.fail("levels", "allowed 0 to 30 (steps dt down to dt/2^levels)" + got(static_cast<double>(levels)));
  r.levels = static_cast<int>(levels);
  const std::int64_t force = s.integer("force_level", -1);
  if (force < -1 || force > levels)
    s.fail("force_level", "allowed -1 (off) or 0 to block_steps.levels (" + std::to_string(levels) + ")" + got(static_cast<double>(force)));
  r.force_level = static_cast<int>(force);
  r.kappa_c = s.positive("kappa_c", r.kappa_c);
  r.eta_damping = s.positive("eta_damping", r.eta_damping);
  const char* rate = r.damping_rate == DampingRate::measured ? "measured" : "bound";
  r.damping_rate = s.choice("damping_rate", {"bound", "measured"}, std::string(rate)) == "measured" ? DampingRate::measured
                                                                                                 : DampingRate::bound;
  r.eta_gap = s.positive("eta_gap", r.eta_gap);
  r.eta_tau = s.positive("eta_tau", r.eta_tau);
  r.eta_a = s.positive("eta_a", r.eta_a);
  r.eta_s = s.positive("eta_s", r.eta_s);
  r.u_floor = s.positive("u_floor", r.u_floor);
  r.list_horizon = s.positive("list_horizon", r.list_horizon);
  const std::int64_t spread = s.integer("level_spread", r.level_spread);
  if (spread < 0 || spread > levels)
    s.fail("level_spread", "allowed 0 (grains in touch share a level) to block_steps.levels (" + std::to_string(levels) + ")" +
                               got(static_cast<double>(spread)));
  r.level_spread = static_cast<int>(spread);
  s.finish();
}

void read_simulation(Section s, Scenario& sc) {
  sc.name = s.text("name", std::filesystem::path(sc.file).stem().string());
  // The default output folder is out/<name>: a name must stay a folder name inside out/.
  if (sc.name.empty() || sc.name == "." || sc.name == ".." || sc.name.find_first_of("/\\") != std::string::npos ||
      std::any_of(sc.name.begin(), sc.name.end(), [](unsigned char c) { return c < 0x20; }))
    s.fail("name", "\"" + sc.name + "\" is not a folder name (it names out/<name>): no '/', '\\', line breaks, \".\" or \"..\"");
  sc.duration = s.positive("duration");
  sc.dt = s.positive("dt");
  if (sc.dt > sc.duration) s.fail("dt", "must not exceed simulation.duration (" + num(sc.duration) + " s)" + got(sc.dt));
  // Step numbers are 64-bit integers and times step * dt: beyond 2^53 steps neither is exact.
  if (!(sc.duration / sc.dt <= 0x1p53))
    s.fail("dt", "gives " + num(sc.duration / sc.dt) + " steps over simulation.duration; at most 2^53 (9e15) are allowed (dt is in seconds)" + got(sc.dt));
  std::array<std::string_view, kIntegrators.size()> integrators;
  for (std::size_t k = 0; k < integrators.size(); ++k) integrators[k] = integrator_name(kIntegrators[k]);
  const std::string integrator = s.choice("integrator", integrators, std::string(integrators[0]));
  sc.integrator = kIntegrators[static_cast<std::size_t>(
      std::find(integrators.begin(), integrators.end(), integrator) - integrators.begin())];
  if (auto b = s.table("block_steps")) {
    if (sc.integrator != Integrator::block_hermite)
      b->fail("levels", "[simulation.block_steps] is read only with simulation.integrator = \"block_hermite\"");
    read_block_steps(*b, sc.block_steps);
  }
  sc.gravity = s.vec3("gravity", {0, 0, -9.81});
  const std::int64_t seed = s.integer("seed", 1);
  if (seed < 0) s.fail("seed", "must be >= 0");
  sc.seed = static_cast<std::uint64_t>(seed);
  sc.overlap_limit = s.positive("overlap_limit", 0.1);
  if (sc.overlap_limit >= 1) s.fail("overlap_limit", "is a fraction of the smaller diameter: allowed (0, 1)" + got(sc.overlap_limit));
  sc.skin = s.has("skin") ? s.positive("skin") : 0.0;
  sc.energy_growth_limit = s.real("energy_growth_limit", 0.5);
  if (sc.energy_growth_limit < 0)
    s.fail("energy_growth_limit", "must be >= 0 (a fraction of the largest kinetic + elastic energy; 0 turns the check off)" +
                                      got(sc.energy_growth_limit));
  s.finish();
}

void read_domain(Section s, Scenario& sc) {
  sc.domain.lower = s.vec3("lower");
  sc.domain.upper = s.vec3("upper");
  sc.domain_where = s.where();
  for (int k = 0; k < 3; ++k)
    if (!(sc.domain.upper[k] > sc.domain.lower[k])) s.fail("upper", "must be above domain.lower on every axis");
  for (const std::string& axis : s.texts("periodic", {})) {
    if (axis != "x" && axis != "y" && axis != "z")
      s.fail("periodic", "\"" + axis + "\" is not an axis; allowed: \"x\", \"y\", \"z\"");
    sc.domain.periodic[static_cast<std::size_t>(axis[0] - 'x')] = true;
  }
  for (const std::string& face : s.texts("open", {})) {
    const auto at = std::find(kBoxFaces.begin(), kBoxFaces.end(), face);
    if (at == kBoxFaces.end())
      s.fail("open", "\"" + face + "\" is not a face of the box; allowed: \"x_min\", \"x_max\", \"y_min\", \"y_max\", "
                     "\"z_min\", \"z_max\"");
    const auto f = static_cast<std::size_t>(at - kBoxFaces.begin());
    if (sc.domain.periodic[f / 2])
      s.fail("open", "\"" + face + "\": the " + std::string(1, static_cast<char>('x' + f / 2)) +
                         " axis is periodic; a face is either open or periodic");
    sc.domain.open[f / 2][f % 2] = true;
  }
  s.finish();
}

void read_material(Section s, Scenario& sc) {
  Material m;
  m.name = s.text("name");
  for (const auto& other : sc.materials)
    if (other.name == m.name) s.fail("name", "material \"" + m.name + "\" is defined twice");
  m.density = s.positive("density");
  m.youngs_modulus = s.positive("youngs_modulus");
  m.poisson = s.real("poisson");
  if (!(m.poisson >= 0 && m.poisson < 0.5)) s.fail("poisson", "allowed range [0, 0.5)" + got(m.poisson));
  s.finish();
  sc.materials.push_back(m);
}

void read_contact(Section s, Scenario& sc) {
  if (auto d = s.table("default")) {
    sc.default_contact = read_contact_spec(*d, integrator_name(sc.integrator));
    d->finish();
  }
  for (Section p : s.tables("pairs")) {
    const auto names = p.texts("materials", {});
    if (names.size() != 2) p.fail("materials", "must name two materials, e.g. [\"glass\", \"steel\"]");
    PairContactSpec pc;
    pc.a = material_named(sc, p, "materials", names[0]);
    pc.b = material_named(sc, p, "materials", names[1]);
    for (const auto& other : sc.pair_contacts)
      if ((other.a == pc.a && other.b == pc.b) || (other.a == pc.b && other.b == pc.a))
        p.fail("materials", "the pair \"" + names[0] + "\", \"" + names[1] + "\" has two [[contact.pairs]] entries");
    pc.spec = read_contact_spec(p, integrator_name(sc.integrator));
    p.finish();
    sc.pair_contacts.push_back(pc);
  }
  s.finish();
}

constexpr double kRounding = 1e-9;  // of a vector's length: components across it that are rounding

// The end of a stretch of motion (`until` of m), later than the end of the one before it.
double stretch_end(Section& m, double& previous) {
  const double until = m.positive("until");
  if (!(until > previous)) m.fail("until", "must be later than the end of the previous stretch (" + num(previous) + " s)" + got(until));
  return previous = until;
}

// A velocity within the plane of normal n (`surface_velocity` of s): components out of the
// plane would move the geometry, refused unless they are rounding (the vector is projected).
Vec3 velocity_in_plane(Section& s, const Vec3& n) {
  const Vec3 v = s.vec3("surface_velocity", {});
  if (const double across = dot(v, n); std::abs(across) > kRounding * norm(v))
    s.fail("surface_velocity", "must lie in the wall's plane (perpendicular to its normal): its component along the normal is " +
                                   num(across) + " m/s; a wall that moves across its plane takes a `motion`");
  return v - dot(v, n) * n;
}

// A rotation about the unit vector `about` (`angular_velocity` of s), which moves no geometry;
// components across it are refused unless they are rounding.
Vec3 rotation_about(Section& s, const Vec3& about, const std::string& what,
                    const std::string& why = "the rotation moves no geometry") {
  const Vec3 omega = s.vec3("angular_velocity", {});
  if (const double off = norm(cross(omega, about)); off > kRounding * norm(omega))
    s.fail("angular_velocity", "must be along " + what + " (" + why + "); its component across it is " + num(off) + " rad/s");
  return dot(omega, about) * about;
}

// A wall's surface motion, which moves no geometry (Wall): constant (surface_velocity within
// a plane, angular_velocity about its normal or axis, `what`) or in stretches of time
// (surface_motion, each with `until` and either of the two); a plane's rotation is about
// `center`.
void read_surface_motion(Section& s, Wall& w, const Vec3& about, const std::string& what) {
  const bool plane = w.shape == WallShape::plane;
  if (s.has("surface_motion")) {
    for (const char* key : {"surface_velocity", "angular_velocity"})
      if (s.has(key)) s.fail(key, "give the surface's motion either as constant values or as surface_motion stretches, not both");
    double previous = 0;
    for (Section m : s.tables("surface_motion")) {
      SurfaceMotion stretch;
      stretch.until = stretch_end(m, previous);
      if (plane) stretch.surface_velocity = velocity_in_plane(m, w.normal);
      stretch.angular_velocity = rotation_about(m, about, what);
      m.finish();
      w.surface_motion.push_back(stretch);
    }
  } else {
    if (plane) w.surface_velocity = velocity_in_plane(s, w.normal);
    w.angular_velocity = rotation_about(s, about, what);
  }
  if (!plane) return;
  const bool turns = !(w.angular_velocity == Vec3{}) ||
                     std::any_of(w.surface_motion.begin(), w.surface_motion.end(),
                                 [](const SurfaceMotion& m) { return !(m.angular_velocity == Vec3{}); });
  if (s.has("center") && !turns)
    s.fail("center", "is the axis of the surface's rotation: give angular_velocity too, or leave center out");
  w.axis_offset = s.vec3("center", w.point) - w.point;
}

// A plane with a hole or a mesh (`what`, named by `key`): no hindered settling (the room a
// wall leaves a grain is measured for whole planes, cylinders and cones).
void refuse_with_hindered_settling(Section& s, const Scenario& sc, const char* key, const std::string& what) {
  if (sc.fluid.hindered)
    s.fail(key, "hindered settling measures the room a whole plane, a cylinder or a cone leaves a grain; " + what +
                    " is not available with fluid.hindered_settling = true yet");
}

// A wall's motion in stretches of constant velocity (a plane's, a cylinder's, a cone's, a mesh's).
void read_motion(Section& s, Wall& w) {
  double previous = 0;
  for (Section m : s.tables("motion")) {
    WallMotion stretch;
    stretch.until = stretch_end(m, previous);
    stretch.velocity = m.vec3("velocity");
    m.finish();
    w.motion.push_back(stretch);
  }
}

// A cylinder (shape = "cylinder") or a cone (shape = "cone"): its axis, size and side; it may
// move in a straight line in stretches (`motion`, as a plane: a lifted tube, a moving hopper)
// and its surface may turn about the axis.
void read_round_wall(Section& s, Wall& w, const std::string& shape) {
  w.shape = shape == "cone" ? WallShape::cone : WallShape::cylinder;
  const std::string keys = w.shape == WallShape::cone ? "point (the centre of its first rim), axis, length, radius, end_radius"
                                                      : "point (on its axis), axis, radius";
  for (const char* key : {"normal", "surface_velocity", "center"})
    if (s.has(key))
      s.fail(key, "is not a " + shape + "'s: a " + shape + " takes " + keys +
                      ", side, material, motion (moving in a straight line) and angular_velocity or surface_motion (turning "
                      "about its axis)");
  w.point = s.vec3("point");
  const Vec3 a = s.vec3("axis");
  if (!std::isnormal(norm(a)))
    s.fail("axis", "must be a non-zero vector along the " + shape + ", with components of ordinary size such as [0, 1, 0]; its "
                   "length is " + num(norm(a)));
  w.axis = a / norm(a);
  if (w.shape == WallShape::cone) {
    w.length = s.positive("length");
    w.radius = s.real("radius");
    w.end_radius = s.real("end_radius");
    for (const auto& [key, r] : {std::pair{"radius", w.radius}, {"end_radius", w.end_radius}})
      if (!(r >= 0)) s.fail(key, "must be at least 0 m (0: the cone's apex)" + got(r));
    if (!(w.radius > 0 || w.end_radius > 0)) s.fail("end_radius", "and radius are both 0: a cone needs one rim wider than a point");
  } else {
    w.radius = s.positive("radius");
  }
  w.inside = s.choice("side", {"inside", "outside"}, std::string("inside")) == "inside";
  read_motion(s, w);
  read_surface_motion(s, w, w.axis, "the " + shape + "'s axis");
}

// A file's bytes, for the scenario's hash (a resume refuses a mesh file that changed).
std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A mesh's turning as a rigid body about the axis through `center` (a mixer's blade, a drum
// with lifters): a constant angular_velocity, or surface_motion stretches of angular_velocity
// (each with `until`), all about the axis of the first that turns (turn_axis), which the
// turned angle is measured about (Wall::turn_to).
Vec3 turning_rate(Section& s) {
  const Vec3 omega = s.vec3("angular_velocity", {});
  if (!(omega == Vec3{}) && !std::isnormal(norm(omega)))
    s.fail("angular_velocity", "must be zero or of ordinary size (its length " + num(norm(omega)) + " rad/s has no direction)");
  return omega;
}

void read_mesh_turning(Section& s, Wall& w) {
  if (s.has("surface_motion")) {
    if (s.has("angular_velocity"))
      s.fail("angular_velocity", "give the mesh's turning either as a constant angular_velocity or as surface_motion stretches, not both");
    double previous = 0;
    for (Section m : s.tables("surface_motion")) {
      SurfaceMotion stretch;
      stretch.until = stretch_end(m, previous);
      if (w.turn_axis == Vec3{}) {
        stretch.angular_velocity = turning_rate(m);
        w.turn_at(stretch.angular_velocity);  // its axis; the stretch sets the rate (Wall::surface_during)
      } else {
        stretch.angular_velocity = rotation_about(m, w.turn_axis, "the axis of the mesh's first turning stretch",
                                                "a mesh's stretches turn it about one axis");
      }
      m.finish();
      w.surface_motion.push_back(stretch);
    }
  } else {
    w.turn_at(turning_rate(s));
  }
  if (s.has("center") && w.turn_axis == Vec3{})
    s.fail("center", "is the axis of the mesh's rotation: give angular_velocity too, or leave center out");
}

// A triangle mesh (shape = "mesh") from an STL or OBJ file (io/mesh_file.hpp), in `units`,
// scaled, turned about an axis through the origin and moved by `translate`, in that order;
// it may move with `motion` as a plane does, and turn.
void read_mesh_wall(Section& s, Scenario& sc, Wall& w, const std::filesystem::path& folder) {
  w.shape = WallShape::mesh;
  refuse_with_hindered_settling(s, sc, "shape", "a mesh");
  for (const char* key : {"point", "normal", "axis", "radius", "end_radius", "length", "side", "hole_radius"})
    if (s.has(key))
      s.fail(key, "is not a mesh's: a mesh takes file, units, scale, rotation_axis, rotation_degrees, translate, material, "
                  "motion, surface_velocity (a conveyor), and angular_velocity or surface_motion with center (it turns as a "
                  "rigid body)");
  const std::filesystem::path given = s.text("file");
  const std::filesystem::path path = (given.is_absolute() ? given : folder / given).lexically_normal();
  if (!std::filesystem::is_regular_file(path))
    s.fail("file", "no such file \"" + path.string() + "\" (relative paths start at the scenario's folder)");
  static constexpr std::array<std::pair<const char*, double>, 5> kUnits = {
      {{"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"um", 1e-6}, {"in", 0.0254}}};
  const std::string unit = s.choice("units", {"m", "cm", "mm", "um", "in"}, std::nullopt);
  double factor = 1;
  for (const auto& [name, metres] : kUnits)
    if (unit == name) factor = metres;
  factor *= s.positive("scale", 1.0);
  const bool turned = s.has("rotation_axis") || s.has("rotation_degrees");
  Vec3 axis{0, 0, 1};
  double angle = 0;
  if (turned) {
    const Vec3 a = s.vec3("rotation_axis");
    if (!std::isnormal(norm(a))) s.fail("rotation_axis", "must be a non-zero vector such as [0, 0, 1]; its length is " + num(norm(a)));
    axis = a / norm(a);
    angle = s.real("rotation_degrees") * M_PI / 180;
  }
  const Vec3 shift = s.vec3("translate", {});
  MeshData data;
  try {
    data = read_mesh_file(path);
  } catch (const MeshFileError& e) {
    s.fail("file", e.what());
  }
  // Rodrigues' rotation of each scaled vertex, then the shift.
  const double c = std::cos(angle), sn = std::sin(angle);
  Vec3 lower{INFINITY, INFINITY, INFINITY}, upper{-INFINITY, -INFINITY, -INFINITY};
  for (Vec3& v : data.vertices) {
    const Vec3 a = factor * v;
    v = (turned ? c * a + sn * cross(axis, a) + (1 - c) * dot(axis, a) * axis : a) + shift;
    for (int k = 0; k < 3; ++k) lower[k] = std::min(lower[k], v[k]), upper[k] = std::max(upper[k], v[k]);
  }
  // A file in another unit than `units` says spans a box a hundred or a thousand times off.
  const double box = norm(sc.domain.upper - sc.domain.lower), span = norm(upper - lower);
  if (span > 20 * box)
    s.fail("units", "the mesh spans " + num(span) + " m read in " + unit + ", " + std::to_string(std::lround(span / box)) +
                        " times the domain's " + num(box) + " m: is the file in another unit (units = \"mm\" reads its numbers as millimetres)?");
  bool meets = true;
  for (int k = 0; k < 3; ++k) meets = meets && upper[k] >= sc.domain.lower[k] && lower[k] <= sc.domain.upper[k];
  const auto text = [](const Vec3& v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; };
  if (!meets)
    s.fail("file", "the mesh lies outside the domain (it spans " + text(lower) + " to " + text(upper) +
                       " m): check units, scale, rotation and translate");
  try {
    w.mesh = std::make_shared<const TriangleMesh>(std::move(data.vertices), std::move(data.triangles));
  } catch (const std::invalid_argument& e) {
    s.fail("file", std::string("the mesh in ") + unit + ": " + e.what() + " (after scaling)");
  }
  read_motion(s, w);
  read_mesh_turning(s, w);
  w.axis_offset = s.vec3("center", {});
  // A conveyor of triangles: its surface moves at surface_velocity in the contact's plane.
  w.surface_velocity = s.vec3("surface_velocity", {});
  if (!(w.surface_velocity == Vec3{}) && (!(w.turn_axis == Vec3{}) || !w.surface_motion.empty()))
    s.fail("surface_velocity", "a mesh's surface velocity is given in the box's frame and would not turn with the mesh: not "
                               "with angular_velocity or surface_motion yet (a conveyor of triangles stands still or moves "
                               "with motion)");
  sc.hash = fnv1a64(file_bytes(path), sc.hash);
}

void read_wall(Section s, Scenario& sc, const std::filesystem::path& folder) {
  Wall w;
  w.material = material_index(sc, s, "material");
  const std::string shape = s.choice("shape", {"plane", "cylinder", "cone", "mesh"}, std::string("plane"));
  if (shape == "mesh") {
    read_mesh_wall(s, sc, w, folder);
    s.finish();
    sc.walls.push_back(w);
    return;
  }
  if (shape != "plane") {
    read_round_wall(s, w, shape);
    s.finish();
    sc.walls.push_back(w);
    return;
  }
  w.point = s.vec3("point");
  const Vec3 n = s.vec3("normal");
  // Its length must be an ordinary double: zero, subnormal or overflowing lengths (1e200
  // squared) would normalise to zero or NaN.
  if (!std::isnormal(norm(n)))
    s.fail("normal", "must be a non-zero vector pointing towards the particles, with components of ordinary size such as [0, 0, 1]; its length is " + num(norm(n)));
  w.normal = n / norm(n);
  if (s.has("hole_radius")) {  // an outlet about `point`
    w.hole_radius = s.positive("hole_radius");
    refuse_with_hindered_settling(s, sc, "hole_radius", "a plane with a hole");
  }
  read_motion(s, w);
  read_surface_motion(s, w, w.normal, "the wall's normal");
  s.finish();
  sc.walls.push_back(w);
}

// A sieve curve as sediment labs report it: sizes d (m) and the percent of the mass finer
// than each. Sizes that look like millimetres are refused: no sieve may reach half the
// box's smallest side, where no grain of a real sample would fit the box.
void read_sieve_curve(Section& s, SizeDistribution& d, const Domain& box) {
  d.kind = SizeDistribution::Kind::table;
  d.sieve = s.reals("d");
  std::vector<double> percent = s.reals("percent_finer_by_mass");
  if (d.sieve.size() < 2) s.fail("d", "give at least two sieve sizes (m), from the finest to the coarsest");
  if (percent.size() != d.sieve.size())
    s.fail("percent_finer_by_mass", "must have one value per entry of d (" + std::to_string(d.sieve.size()) + "), got " +
                                        std::to_string(percent.size()));
  for (std::size_t k = 0; k < d.sieve.size(); ++k) {
    if (!(d.sieve[k] > 0)) s.fail("d", "sieve sizes must be > 0 (m)" + got(d.sieve[k]));
    if (k > 0 && !(d.sieve[k] > d.sieve[k - 1])) s.fail("d", "sieve sizes must increase strictly" + got(d.sieve[k]));
    if (k > 0 && !(percent[k] >= percent[k - 1]))
      s.fail("percent_finer_by_mass", "must not decrease: the mass finer than a larger sieve is at least as large" + got(percent[k]));
  }
  if (percent.front() != 0 || percent.back() != 100)
    s.fail("percent_finer_by_mass", "must run from 0 (nothing finer than the first size) to 100 (all finer than the last), got " +
                                        num(percent.front()) + " to " + num(percent.back()));
  double side = box.length(0);
  for (int k = 1; k < 3; ++k) side = std::min(side, box.length(k));
  if (d.sieve.back() >= 0.5 * side)
    s.fail("d", "did you mean metres? d = " + num(d.sieve.back()) + " looks like millimetres: it is at least half the box's smallest side (" +
                    num(side) + " m); sizes are in metres (" + num(d.sieve.back()) + " mm = " + num(1e-3 * d.sieve.back()) + ")");
  for (double p : percent) d.finer.push_back(p / 100);
  d.weigh_table();
}

SizeDistribution read_distribution(Section s, const Domain& box) {
  SizeDistribution d;
  const std::string type = s.choice("type", {"single", "uniform", "lognormal", "talbot", "table"}, std::nullopt);
  if (type == "table") {
    read_sieve_curve(s, d, box);
  } else if (type == "single") {
    d.kind = SizeDistribution::Kind::single;
    d.diameter = s.positive("diameter");
  } else if (type == "uniform" || type == "talbot") {
    d.kind = type == "uniform" ? SizeDistribution::Kind::uniform : SizeDistribution::Kind::talbot;
    if (type == "talbot" && s.has("spread")) {  // Sigma = ln(d_max/d_min), the paper's spread
      if (s.has("d_min")) s.fail("spread", "give either d_min or spread = ln(d_max/d_min), not both");
      d.d_max = s.positive("d_max");
      d.d_min = d.d_max * std::exp(-s.positive("spread"));
    } else {
      d.d_min = s.positive("d_min");
      d.d_max = s.positive("d_max");
    }
    if (!(d.d_max > d.d_min)) s.fail("d_max", "must be larger than d_min");
    if (type == "talbot") d.exponent = s.real("exponent");
  } else {
    d.kind = SizeDistribution::Kind::lognormal;
    d.median = s.positive("median");
    d.sigma = s.positive("sigma");
    d.d_min = s.has("d_min") ? s.positive("d_min") : 0.0;
    d.d_max = s.has("d_max") ? s.positive("d_max") : 0.0;
    if (d.d_max > 0 && d.d_max <= d.d_min) s.fail("d_max", "must be larger than d_min");
    if (!(d.acceptance() >= SizeDistribution::kMinAcceptance))
      s.fail("median", "only a fraction " + num(d.acceptance()) + " of the lognormal draws (median " + num(d.median) +
                           " m, sigma " + num(d.sigma) + ") lie within [d_min, d_max]; at least " +
                           num(SizeDistribution::kMinAcceptance) + " is needed (diameters are in metres: is the median in mm?)");
  }
  s.finish();
  return d;
}

void read_region(Section& s, ParticleSource& src, const Domain& domain) {
  src.lower = s.vec3("lower");
  src.upper = s.vec3("upper");
  for (int k = 0; k < 3; ++k) {
    if (!(src.upper[k] > src.lower[k])) s.fail("upper", "must be above lower on every axis");
    if (src.lower[k] < domain.lower[k]) s.fail("lower", "the region [lower, upper] must lie inside the domain (below domain.lower)");
    if (src.upper[k] > domain.upper[k]) s.fail("upper", "the region [lower, upper] must lie inside the domain (above domain.upper)");
  }
  src.velocity = s.vec3("velocity", {});
}

SizeDistribution required_distribution(Section& s, const std::string& kind, const Domain& box) {
  auto dist = s.table("distribution");
  if (!dist) s.fail("distribution", "is required for source = \"" + kind + "\", e.g. { type = \"single\", diameter = 0.002 }");
  return read_distribution(*dist, box);
}

// A scenario has at most one source whose grains arrive during the run.
void refuse_second_arrival(Section& s, const Scenario& sc) {
  if (const ParticleSource* other = inflow_source(sc))
    s.fail("source", "a scenario has at most one inflow or insertion source (another one is at line " +
                         std::to_string(other->where.line) + ")");
}

// The mass an inflow or insertion releases at most (kg, 0: no limit).
void read_mass_limit(Section& s, ParticleSource& src) {
  src.mass_limit = s.real("mass_limit", 0.0);
  if (!(src.mass_limit >= 0) || !std::isfinite(src.mass_limit))
    s.fail("mass_limit", "allowed 0 (no limit) or a mass > 0 (kg)" + got(src.mass_limit));
}

// Grains placed at random in a region during the run (docs/scenario.md, source =
// "insertion"): the region, inside the domain and wide enough for the largest grain on every
// side; a mass rate, a total, or both.
void read_insertion(Section& s, ParticleSource& src, const Scenario& sc) {
  src.kind = ParticleSource::Kind::insertion;
  refuse_second_arrival(s, sc);
  src.sizes = required_distribution(s, "insertion", sc.domain);
  const double d_max = src.sizes.largest();
  InsertionRegion& r = src.region;
  if (s.choice("region", {"box", "cylinder"}, std::string("box")) == "box") {
    r.shape = InsertionRegion::Shape::box;
    r.lower = s.vec3("lower");
    r.upper = s.vec3("upper");
    for (int k = 0; k < 3; ++k) {
      if (!(r.upper[k] - r.lower[k] > d_max))
        s.fail("upper", "the region must be wider than the largest grain (" + num(d_max) + " m) along " + "xyz"[k] +
                            ": upper - lower is " + num(r.upper[k] - r.lower[k]) + " m");
      if (r.lower[k] < sc.domain.lower[k]) s.fail("lower", "the region must lie inside the domain (below domain.lower)");
      if (r.upper[k] > sc.domain.upper[k]) s.fail("upper", "the region must lie inside the domain (above domain.upper)");
    }
  } else {
    r.shape = InsertionRegion::Shape::cylinder;
    r.point = s.vec3("point");
    const Vec3 a = s.vec3("axis");
    if (!std::isnormal(norm(a)))
      s.fail("axis", "must be a non-zero vector along the region's axis, with components of ordinary size such as [0, 0, 1]; its "
                     "length is " + num(norm(a)));
    r.axis = a / norm(a);
    r.radius = s.positive("radius");
    r.length = s.positive("length");
    if (!(r.radius > 0.5 * d_max)) s.fail("radius", "must exceed the largest grain's radius (" + num(0.5 * d_max) + " m)" + got(r.radius));
    if (!(r.length > d_max)) s.fail("length", "must exceed the largest grain's diameter (" + num(d_max) + " m)" + got(r.length));
    const Vec3 u = perpendicular(r.axis), v = cross(r.axis, u);
    for (const double end : {0.0, r.length})  // its rims' extreme points along x, y, z lie inside the domain
      for (int k = 0; k < 3; ++k) {
        const double reach = r.radius * std::hypot(u[k], v[k]), centre = r.point[k] + end * r.axis[k];
        if (!sc.domain.periodic[k] && (centre - reach < sc.domain.lower[k] || centre + reach > sc.domain.upper[k]))
          s.fail("radius", std::string("the region must lie inside the domain: its rim reaches ") + "xyz"[k] + " = " +
                               num(centre - reach < sc.domain.lower[k] ? centre - reach : centre + reach) + " m");
      }
  }
  src.velocity = s.vec3("velocity", {});
  src.mass_rate = s.real("mass_rate", 0.0);
  if (!(src.mass_rate >= 0) || !std::isfinite(src.mass_rate))
    s.fail("mass_rate", "allowed a mass per time > 0 (kg/s), or 0 for the whole mass_limit at once" + got(src.mass_rate));
  read_mass_limit(s, src);
  if (src.mass_rate == 0 && src.mass_limit == 0)
    s.fail("mass_rate", "an insertion needs a mass_rate (kg/s), a mass_limit (kg, inserted at once) or both");
  src.start = s.real("start", 0.0);
  if (!(src.start >= 0) || !std::isfinite(src.start)) s.fail("start", "allowed a time >= 0 (s)" + got(src.start));
}

// The virtual column of the sedimentation experiment (docs/sedimentation.md).
void read_inflow(Section& s, ParticleSource& src, const Scenario& sc) {
  src.kind = ParticleSource::Kind::inflow;
  refuse_second_arrival(s, sc);
  const Domain& box = sc.domain;
  if (!box.periodic[0] || !box.periodic[1])
    s.fail("source", "\"inflow\" needs a domain periodic in x and y (the column's sides wrap): domain.periodic = [\"x\", \"y\"]");
  if (sc.gravity.x != 0 || sc.gravity.y != 0 || sc.gravity.z > 0)
    s.fail("source", "\"inflow\" falls along -z: simulation.gravity must point along -z (or be zero)");
  src.solid_fraction = s.positive("solid_fraction");
  if (src.solid_fraction > 0.3)
    s.fail("solid_fraction", "the column's phi_0; its random placement slows near jamming (0.38 for one size): allowed (0, 0.3]" +
                                 got(src.solid_fraction));
  src.sizes = required_distribution(s, "inflow", box);
  const double d_max = src.sizes.largest();
  // The entering grains, the largest included, must lie inside the domain. The value is
  // compared with the bounds the message prints.
  const double entry_low = box.lower.z + 0.5 * d_max, entry_high = box.upper.z - 0.5 * d_max;
  if (!(entry_low < entry_high)) {
    const bool unbounded = src.sizes.kind == SizeDistribution::Kind::lognormal && !(src.sizes.d_max > 0);
    s.fail("distribution", "its largest grain, d = " + num(d_max) + " m" +
                               (unbounded ? " (the median times e^(6 sigma): this log-normal has no d_max)" : "") +
                               ", cannot enter: it does not fit in the domain's height, " + num(box.length(2)) +
                               " m; allowed: a largest diameter below it (give the distribution a d_max)");
  }
  src.entry_height = s.real("entry_height", box.lower.z + 2 * box.length(0));
  if (!(src.entry_height > entry_low && src.entry_height <= entry_high))
    s.fail("entry_height", "the entering grains must lie inside the domain: allowed (" + num(entry_low) + ", " + num(entry_high) +
                               "] m, a largest radius inside the domain (the default is 2 L above domain.lower.z)" +
                               got(src.entry_height));
  const double density = sc.materials[static_cast<std::size_t>(src.material)].density;
  if (s.has("fall_speed")) {
    src.fall_speed = s.positive("fall_speed");
  } else {
    if (!sc.fluid.enabled)
      s.fail("fall_speed", "is required without [fluid]: the default, Rubey's settling speed, needs the fluid's density and viscosity");
    if (!(sc.fluid.density < density) || !(norm(sc.gravity) > 0))
      s.fail("fall_speed", "is required here: the default, Rubey's settling speed, needs gravity and grains denser than the fluid");
    src.fall_speed = rubey_speed(density, sc.fluid.density, sc.fluid.viscosity, d_max, norm(sc.gravity));
  }
  // A grain due during a step enters up to u_r dt below the entry plane: that must stay inside
  // the domain (a speed such as 1e300 would release the whole column at the first step).
  const double speed_limit = (src.entry_height - entry_low) / sc.dt;
  if (!(src.fall_speed < speed_limit))
    s.fail("fall_speed", std::string(s.has("fall_speed") ? "" : "(Rubey's settling speed of the largest grain, the default) ") +
                             "carries the column " + num(src.fall_speed * sc.dt) +
                             " m in one step (fall_speed * simulation.dt), past the domain's floor: allowed (0, " +
                             num(speed_limit) + ") m/s, (entry_height - d_max/2 - domain.lower.z) / dt" + got(src.fall_speed));
  read_mass_limit(s, src);
  src.omega_star_rms = s.real("omega_star_rms", 0.0);
  if (!(src.omega_star_rms >= 0)) s.fail("omega_star_rms", "must be >= 0 (0: no initial spin)" + got(src.omega_star_rms));
  // Each spin component is normal with sd 2 u_r Omega*_rms / d (source/inflow.cpp), within 9
  // sd (Box-Muller): the largest grain's rotational energy must be a finite double.
  const double inertia = M_PI / 60 * density * std::pow(d_max, 5);
  const double spin_limit = std::sqrt(std::numeric_limits<double>::max()) / std::sqrt(0.5 * inertia * 3 * 9 * 9) * d_max / (2 * src.fall_speed);
  if (!(src.omega_star_rms <= spin_limit))
    s.fail("omega_star_rms", "gives the largest grains spins whose rotational energy is not a finite double: allowed [0, " +
                                 num(spin_limit) + "]" + got(src.omega_star_rms));
}

void read_particles(Section s, Scenario& sc, const std::filesystem::path& folder, bool particle_files) {
  ParticleSource src;
  src.where = s.where();
  src.key_where = s.key_locations();
  const std::string kind = s.choice("source", {"csv", "file", "lattice", "random", "inflow", "insertion"}, std::nullopt);
  // A file source's rows name their own materials.
  if (kind != "file") src.material = material_index(sc, s, "material");
  if (kind == "csv" || kind == "file") {
    src.kind = kind == "csv" ? ParticleSource::Kind::csv : ParticleSource::Kind::file;
    const std::filesystem::path f = s.text("file");
    src.file = (f.is_absolute() ? f : folder / f).lexically_normal().string();
    if (particle_files && !std::filesystem::is_regular_file(src.file)) s.fail("file", "no such file \"" + src.file + "\" (relative paths start at the scenario's folder)");
    src.overlap_tolerance = s.real("overlap_tolerance", 0.01);
    if (src.overlap_tolerance < 0) s.fail("overlap_tolerance", "must be >= 0 (a fraction of the smaller diameter)" + got(src.overlap_tolerance));
    if (src.overlap_tolerance > sc.overlap_limit)
      s.fail("overlap_tolerance", "must not exceed simulation.overlap_limit (" + num(sc.overlap_limit) +
                                      "): a larger overlap stops the run at its first step" + got(src.overlap_tolerance));
  } else if (kind == "lattice") {
    src.kind = ParticleSource::Kind::lattice;
    read_region(s, src, sc.domain);
    src.diameter = s.positive("diameter");
    src.spacing = s.positive("spacing", src.diameter);
    if (src.spacing < src.diameter) s.fail("spacing", "must be at least the diameter " + num(src.diameter) + " m (particles would overlap)" + got(src.spacing));
  } else if (kind == "random") {
    src.kind = ParticleSource::Kind::random;
    read_region(s, src, sc.domain);
    src.solid_fraction = s.positive("solid_fraction");
    if (src.solid_fraction > 0.4)
      s.fail("solid_fraction", "random sequential placement jams near 0.38 for one size: allowed (0, 0.4]" + got(src.solid_fraction));
    src.sizes = required_distribution(s, kind, sc.domain);
  } else if (kind == "insertion") {
    read_insertion(s, src, sc);
  } else {
    read_inflow(s, src, sc);
  }
  s.finish();
  sc.sources.push_back(src);
}

void read_output(Section s, Scenario& sc) {
  sc.output.dir = s.text("dir", "");
  sc.output.vtk_interval = s.real("vtk_interval", sc.duration / 50);
  sc.output.series_interval = s.real("series_interval", sc.duration / 200);
  if (sc.output.vtk_interval < 0) s.fail("vtk_interval", "must be >= 0 (0 writes no frames)");
  sc.output.contacts = s.flag("contacts", true);
  if (sc.output.series_interval < 0) s.fail("series_interval", "must be >= 0 (0 writes every step)");
  sc.output.track = s.integers("track", {});
  sc.output.track_interval = s.real("track_interval", sc.output.series_interval);
  if (sc.output.track_interval < 0) s.fail("track_interval", "must be >= 0 (0 writes every step)");
  sc.output.checkpoint_every_steps = s.integer("checkpoint_every_steps", 0);
  if (sc.output.checkpoint_every_steps < 0) s.fail("checkpoint_every_steps", "must be >= 0 (0: none by step count)");
  sc.output.checkpoint_every_seconds = s.real("checkpoint_every_seconds", 600);
  if (!(sc.output.checkpoint_every_seconds >= 0)) s.fail("checkpoint_every_seconds", "must be >= 0 (0: none by wall-clock time)");
  sc.output.where = s.where("track");
  s.finish();
}

// One column of [fluid.kurose_komori]: absent means zero at every point.
std::vector<double> eta_column(Section& s, std::string_view key, std::size_t n) {
  if (!s.has(key)) return std::vector<double>(n, 0.0);
  std::vector<double> v = s.reals(key);
  if (v.size() != n) s.fail(key, "must have one value per entry of re (" + std::to_string(n) + "), got " + std::to_string(v.size()));
  return v;
}

void read_fluid(Section s, Scenario& sc) {
  Fluid& f = sc.fluid;
  f.enabled = true;
  f.density = s.positive("density");
  f.viscosity = s.positive("kinematic_viscosity");
  f.buoyancy = s.flag("buoyancy", true);
  f.drag = s.flag("drag", true);
  f.drag_cap = s.flag("drag_cap", true);
  if (!f.drag && s.has("drag_cap")) s.fail("drag_cap", "is used only with drag = true");
  f.added_mass = s.flag("added_mass", true);
  f.stokes_torque = s.flag("stokes_torque", true);
  f.hindered = s.flag("hindered_settling", false);
  if (s.has("hindered_ball_ratio")) {
    if (!f.hindered) s.fail("hindered_ball_ratio", "is used only with hindered_settling = true");
    f.hindered_ball_ratio = s.real("hindered_ball_ratio");
    if (!(f.hindered_ball_ratio >= 2.5) || !std::isfinite(f.hindered_ball_ratio))
      s.fail("hindered_ball_ratio", "the ball around each grain must be at least 2.5 grain radii (default 3)" + got(f.hindered_ball_ratio));
  }
  if (f.hindered && !f.drag) s.fail("hindered_settling", "hinders the drag: it needs drag = true");
  sc.fluid_where = s.where("hindered_ball_ratio");
  const std::string lift = s.choice("lift", {"none", "kurose_komori", "loth"}, "none");
  f.lift = lift == "kurose_komori" ? SpinModel::kurose_komori : lift == "loth" ? SpinModel::loth : SpinModel::none;
  if (auto t = s.table("kurose_komori")) {
    if (f.lift != SpinModel::kurose_komori)
      s.fail("kurose_komori", "the eta tables are used only with fluid.lift = \"kurose_komori\"");
    f.eta.re = t->reals("re");
    if (f.eta.re.empty()) t->fail("re", "must hold at least one Reynolds number");
    for (std::size_t k = 0; k < f.eta.re.size(); ++k) {
      if (!(f.eta.re[k] >= 0)) t->fail("re", "Reynolds numbers must be >= 0" + got(f.eta.re[k]));
      if (k > 0 && !(f.eta.re[k] > f.eta.re[k - 1])) t->fail("re", "must increase strictly");
    }
    f.eta.eta1 = eta_column(*t, "eta1", f.eta.re.size());
    f.eta.eta2 = eta_column(*t, "eta2", f.eta.re.size());
    f.eta.eta3 = eta_column(*t, "eta3", f.eta.re.size());
    t->finish();
  }
  s.finish();
}

// The largest diameter the scenario's generated sources can hold (0 with particle files only).
double largest_generated(const Scenario& sc) {
  double d = 0;
  for (const ParticleSource& src : sc.sources)
    d = std::max(d, src.kind == ParticleSource::Kind::lattice ? src.diameter
                    : src.kind == ParticleSource::Kind::csv || src.kind == ParticleSource::Kind::file ? 0.0
                                                              : src.sizes.largest());
  return d;
}

// The smallest diameter the scenario's generated sources can hold (0 with CSV files only).
double smallest_generated(const Scenario& sc) {
  double d = 0;
  for (const ParticleSource& src : sc.sources) {
    const double here = src.kind == ParticleSource::Kind::lattice ? src.diameter
                        : src.kind == ParticleSource::Kind::csv   ? 0.0
                                                                  : src.sizes.smallest();
    if (here > 0) d = d > 0 ? std::min(d, here) : here;
  }
  return d;
}

// type = "profiles": the slices (a count, or a thickness that divides z_range) and the size
// classes (given edges, or three classes of equal width in ln d over the scenario's sizes).
void read_profile_slices(Section& s, AnalysisSpec& a, const Scenario& sc) {
  for (const auto& other : sc.analyses)
    if (other.kind == AnalysisSpec::Kind::profiles)
      s.fail("type", "a scenario has at most one \"profiles\" analysis (it writes the profiles/ folder): \"" + other.name +
                         "\" is one already");
  const double range = a.z_high - a.z_low;
  if (s.has("slice") && s.has("slices")) s.fail("slice", "give either slice (a thickness, m) or slices (a count), not both");
  if (s.has("slice")) {
    const double slice = s.positive("slice");
    const double count = std::round(range / slice);
    if (count < 1 || count > 100000 || std::abs(count * slice - range) > 1e-9 * range)
      s.fail("slice", "z_range (" + num(range) + " m) must be a whole number (1 to 100000) of slices of " + num(slice) +
                          " m; or give slices, a count");
    a.profile_slices = static_cast<int>(count);
  } else {
    const std::int64_t count = s.integer("slices", 20);
    if (count < 1 || count > 100000) s.fail("slices", "allowed 1 to 100000, got " + std::to_string(count));
    a.profile_slices = static_cast<int>(count);
  }
  if (s.has("class_edges")) {
    a.class_edges = s.reals("class_edges");
    if (a.class_edges.size() < 2) s.fail("class_edges", "give at least two diameters (m): the edges of one class or more");
    for (std::size_t k = 0; k < a.class_edges.size(); ++k)
      if (!(a.class_edges[k] > 0) || (k > 0 && !(a.class_edges[k] > a.class_edges[k - 1])))
        s.fail("class_edges", "must be diameters > 0 (m), increasing strictly" + got(a.class_edges[k]));
    return;
  }
  const double lo = smallest_generated(sc), hi = largest_generated(sc);
  if (lo == 0) s.fail("class_edges", "is required when no source gives a size range (CSV files only): diameters (m), increasing");
  if (lo == hi) {
    a.class_edges = {lo, hi};  // one size: one class
    return;
  }
  for (int k = 0; k <= 3; ++k) a.class_edges.push_back(lo * std::pow(hi / lo, k / 3.0));
  a.class_edges.back() = hi;
}

// Each result is a column of series.csv and a key of run.json's results: none may be a
// built-in column (or, with an inflow, one of its results) or a result of another analysis.
void check_result_names(const Section& s, const AnalysisSpec& a, const Scenario& sc) {
  const std::vector<std::string> mine = analysis_result_names(a);
  auto listed = [](const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
    return text;
  };
  const std::string these = "\"" + a.name + "\" names this analysis's results " + listed(mine) + ", but ";
  const std::string allowed = "; allowed: a name whose results differ from every column and result";
  const std::vector<std::string> columns = series_columns(sc);
  for (const std::string& name : mine) {
    if (std::find(columns.begin(), columns.end(), name) != columns.end())
      s.fail("name", these + name + " is a built-in column of series.csv (" + listed(columns) + ")" + allowed);
    if (inflow_source(sc) && name.starts_with("inflow_"))
      s.fail("name", these + name + " begins with inflow_, the prefix of the inflow's results in run.json (inflow_F, "
                     "inflow_Q, inflow_released, ...: docs/sedimentation.md)" + allowed);
    for (std::size_t k = 0; k < sc.analyses.size(); ++k) {
      const std::vector<std::string> theirs = analysis_result_names(sc.analyses[k]);
      if (std::find(theirs.begin(), theirs.end(), name) != theirs.end())
        s.fail("name", these + name + " is also a result of analyses[" + std::to_string(k) + "] (name \"" +
                           sc.analyses[k].name + "\": " + listed(theirs) + ")" + allowed);
    }
  }
}

void read_analysis(Section s, Scenario& sc) {
  AnalysisSpec a;
  using Kind = AnalysisSpec::Kind;
  const std::string type =
      s.choice("type", {"solid_fraction", "coordination", "deposit_height", "porosity", "segregation", "kinetic_energy", "profiles"},
               std::nullopt);
  a.kind = type == "solid_fraction" ? Kind::solid_fraction
           : type == "coordination" ? Kind::coordination
           : type == "deposit_height" ? Kind::deposit_height
           : type == "porosity"       ? Kind::porosity
           : type == "segregation"    ? Kind::segregation
           : type == "profiles"       ? Kind::profiles
                                      : Kind::kinetic_energy;
  a.name = s.text("name", type);
  // The experiment's measures take the box's x length as L and heights from domain.lower.z.
  const double L = sc.domain.length(0), floor = sc.domain.lower.z;
  if (a.kind == Kind::deposit_height) {
    a.slice_rule = s.choice("rule", {"surface", "slices"}, "surface") == "slices";
    const std::string rule = a.slice_rule ? "slices" : "surface", other = a.slice_rule ? "surface" : "slices";
    for (const char* key : a.slice_rule ? std::vector<const char*>{"window"} : std::vector<const char*>{"slice", "slices", "threshold"})
      if (s.has(key)) s.fail(key, "is a key of rule = \"" + other + "\" only (this entry's rule is \"" + rule + "\")");
    if (a.slice_rule) {
      a.slices.floor = s.real("floor", floor);
      a.slices.slice = s.positive("slice", 0.1 * L);
      const std::int64_t slices = s.integer("slices", 10);
      if (slices < 1 || slices > 1000000) s.fail("slices", "allowed 1 to 1000000, got " + std::to_string(slices));
      a.slices.slices = static_cast<int>(slices);
      a.slices.threshold = s.real("threshold", 0.6);
      if (!(a.slices.threshold > 0 && a.slices.threshold < 1)) s.fail("threshold", "is a solid fraction: allowed (0, 1)" + got(a.slices.threshold));
    } else {
      a.surface.floor = s.real("floor", floor);
      a.surface.top = sc.domain.upper.z;
      const double d_max = largest_generated(sc);
      if (d_max == 0 && !s.has("window"))
        s.fail("window", "is required when no source gives a largest diameter (CSV files only): the thickness (m) of the sliding window, about the largest grain's diameter");
      a.surface.window = s.positive("window", d_max);
      // The rule bins the height in steps of window/8: at most a million of them.
      const double height = a.surface.top - a.surface.floor;
      if (!(a.surface.window <= height && a.surface.window >= height / 125000))
        s.fail("window", "allowed [" + num(height / 125000) + ", " + num(height) +
                             "] m: at most the domain's height above the floor, at least 1/125000 of it" + got(a.surface.window));
    }
  } else if (a.kind != Kind::kinetic_energy) {
    const auto z = s.has("z_range")             ? s.reals("z_range")
                   : a.kind == Kind::porosity ? std::vector<double>{floor + 0.15 * L, floor + 0.35 * L}
                   : a.kind == Kind::profiles ? std::vector<double>{floor, sc.domain.upper.z}
                                              : s.reals("z_range");
    if (z.size() != 2 || !(z[1] > z[0])) s.fail("z_range", "must be [z_low, z_high] with z_high > z_low");
    if (z[0] < sc.domain.lower.z || z[1] > sc.domain.upper.z)
      s.fail("z_range", "[" + num(z[0]) + ", " + num(z[1]) + "] m reaches outside the domain: allowed within [" +
                            num(sc.domain.lower.z) + ", " + num(sc.domain.upper.z) + "] (domain.lower.z, domain.upper.z)");
    a.z_low = z[0];
    a.z_high = z[1];
  }
  if (a.kind == Kind::profiles) read_profile_slices(s, a, sc);
  if (a.kind == Kind::porosity) {
    constexpr std::int64_t most = 10'000'000;  // a standard error below 1.6e-4, seconds per row
    const std::int64_t points = s.integer("points", a.points);
    if (points < 1 || points > most)
      s.fail("points", "allowed 1 to " + std::to_string(most) +
                           " (65536 give a standard error below 0.002), got " +
                           std::to_string(points));
    a.points = static_cast<long>(points);
    const std::int64_t seed = s.integer("seed", static_cast<std::int64_t>(sc.seed));
    if (seed < 0) s.fail("seed", "must be >= 0");
    a.seed = static_cast<std::uint64_t>(seed);
  }
  if (a.kind == Kind::segregation) {
    const double third = largest_generated(sc) / 3;
    if (third == 0 && !s.has("small_diameter"))
      s.fail("small_diameter", "is required when no source gives a largest diameter (CSV files only): grains below it count as small");
    a.small_diameter = s.positive("small_diameter", third);
  }
  for (const auto& other : sc.analyses)
    if (other.name == a.name) s.fail("name", "two analyses are named \"" + a.name + "\"; give each its own name");
  check_result_names(s, a, sc);
  s.finish();
  sc.analyses.push_back(a);
}

// [[stop]]: a condition on one result of the analyses, checked at every series.csv row.
void read_stop(Section s, Scenario& sc) {
  StopSpec st;
  st.when = s.text("when");
  std::string names;
  bool known = false;
  for (const AnalysisSpec& a : sc.analyses)
    for (const std::string& name : analysis_result_names(a)) {
      known = known || name == st.when;
      names += (names.empty() ? "" : ", ") + name;
    }
  if (!known)
    s.fail("when", "\"" + st.when + "\" is not a result of the [[analyses]]; their results are: " +
                       (names.empty() ? "none (add an [[analyses]] entry)" : names));
  const bool least = s.has("at_least"), most = s.has("at_most");
  if (least == most)
    s.fail(least ? "at_most" : "at_least", "give exactly one of at_least (stop once the value is >= it) and at_most (<= it)");
  st.at_least = least;
  st.limit = s.real(least ? "at_least" : "at_most");
  st.after = s.real("after", 0.0);
  if (!(st.after >= 0)) s.fail("after", "must be >= 0 (s; the condition is not checked before this time)" + got(st.after));
  st.after_inflow = s.flag("after_inflow", false);
  if (st.after_inflow) {
    const ParticleSource* inflow = inflow_source(sc);
    if (!inflow || !(inflow->mass_limit > 0))
      s.fail("after_inflow", "needs a [[particles]] source = \"inflow\" or \"insertion\" with a mass_limit (kg): the condition is "
                             "checked once it has released its last grain" +
                                 std::string(!inflow ? "; the scenario has no inflow or insertion" : "; its source has no mass_limit"));
  }
  s.finish();
  sc.stops.push_back(st);
}

void read_search(Section s, Scenario& sc) {
  const bool multilevel = s.choice("method", {"cell", "multilevel"}, "cell") == "multilevel";
  sc.search.method = multilevel ? SearchSpec::Method::multilevel : SearchSpec::Method::cell;
  if (s.has("levels")) {
    if (!multilevel) s.fail("levels", "is a key of method = \"multilevel\" only");
    const std::int64_t levels = s.integer("levels", 0);
    if (levels < 1 || levels > MultiLevelGrid::kMaxLevels)
      s.fail("levels", "allowed 1 to " + std::to_string(MultiLevelGrid::kMaxLevels) + " (omit it for the automatic choice), got " +
                           std::to_string(levels));
    sc.search.levels = static_cast<int>(levels);
  }
  const std::int64_t sort_every = s.integer("sort_every", sc.search.sort_every);
  if (sort_every < 0) s.fail("sort_every", "allowed 0 (never) or a positive number of steps, got " + std::to_string(sort_every));
  sc.search.sort_every = sort_every;
  s.finish();
}

void read_parallel(Section s, Scenario& sc) {
  if (sc.integrator == Integrator::block_hermite)
    s.fail(s.has("counts") ? "counts" : "balance",
           "block steps share out the active particles among the processes, not the box into subdomains: "
           "[parallel] is read only with a fixed-step integrator (docs/parallel.md)");
  const std::vector<std::int64_t> counts = s.integers("counts", {0, 0, 0});
  if (counts.size() != 3) s.fail("counts", "must be three integers (subdomains along x, y and z), got " + std::to_string(counts.size()));
  for (std::size_t a = 0; a < 3; ++a) {
    if (counts[a] < 0 || counts[a] > kMaxSubdomains)
      s.fail("counts", "allowed 0 (an automatic count along the axis) or 1 to " + std::to_string(kMaxSubdomains) +
                           " subdomains along each axis, got " + std::to_string(counts[a]));
    sc.parallel.counts[a] = static_cast<int>(counts[a]);
  }
  sc.parallel.where = s.where("counts");
  sc.parallel.balance = s.choice("balance", {"work", "none"}, "work") == "work";
  s.finish();
}

}  // namespace

AnalysisSpec load_analysis_text(const Scenario& sc, const std::string& text, const std::string& origin) {
  toml::table table;
  try {
    table = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    throw InputError(origin, static_cast<long>(e.source().begin.line), "", "not valid TOML: " + std::string(e.description()));
  }
  Scenario alone = sc;  // its own name space: the scenario's analyses do not clash with it
  alone.analyses.clear();
  read_analysis(Section(table, "", origin), alone);
  return alone.analyses.front();
}

Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides) {
  return load_scenario_text(read_text(path), path, overrides, true);
}

Scenario load_scenario_text(const std::string& text, const std::string& path, const std::vector<std::string>& overrides,
                            bool particle_files) {
  Scenario sc;
  sc.file = path;
  sc.text = text;
  sc.overrides = overrides;
  sc.hash = fnv1a64(text);
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<long>(e.source().begin.line), "", "not valid TOML: " + std::string(e.description()));
  }
  for (const auto& o : overrides) {
    apply_override(root, o);
    sc.hash = fnv1a64(o, sc.hash);
  }
  const auto folder = std::filesystem::path(path).parent_path();
  Section top(root, "", path);
  auto sim = top.table("simulation");
  if (!sim) top.fail("simulation", "is required: [simulation] with duration and dt");
  read_simulation(*sim, sc);
  auto domain = top.table("domain");
  if (!domain) top.fail("domain", "is required: [domain] with lower and upper corners");
  read_domain(*domain, sc);
  for (Section m : top.tables("materials")) read_material(m, sc);
  if (sc.materials.empty()) top.fail("materials", "at least one [[materials]] entry is required");
  if (auto c = top.table("contact")) read_contact(*c, sc);
  if (auto f = top.table("fluid")) read_fluid(*f, sc);
  for (Section w : top.tables("walls")) read_wall(w, sc, folder);
  for (Section p : top.tables("particles")) read_particles(p, sc, folder, particle_files);
  if (sc.sources.empty()) top.fail("particles", "at least one [[particles]] source is required");
  if (auto o = top.table("output")) read_output(*o, sc);
  else read_output(Section(toml::table{}, "output", path), sc);
  for (Section a : top.tables("analyses")) read_analysis(a, sc);
  for (Section st : top.tables("stop")) read_stop(st, sc);
  if (auto s = top.table("search")) read_search(*s, sc);
  if (auto p = top.table("parallel")) read_parallel(*p, sc);
  top.finish();
  return sc;
}

}  // namespace tsubu
