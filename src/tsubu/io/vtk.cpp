#include "tsubu/io/vtk.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <type_traits>

#include "tsubu/io/checked_file.hpp"
#include "tsubu/world/mesh.hpp"

namespace tsubu {

namespace {

std::string base64(const void* data, std::size_t n) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  for (std::size_t i = 0; i < n; i += 3) {
    const unsigned v = static_cast<unsigned>(b[i]) << 16 | (i + 1 < n ? b[i + 1] << 8 : 0) | (i + 2 < n ? b[i + 2] : 0);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < n ? table[(v >> 6) & 63] : '=';
    out += i + 2 < n ? table[v & 63] : '=';
  }
  return out;
}

// VTK's inline binary layout: base64(UInt64 byte count) followed by base64(raw bytes).
template <class T>
void data_array(std::ostream& f, const char* type, const char* name, int components, const std::vector<T>& values) {
  const std::uint64_t bytes = values.size() * sizeof(T);
  f << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\"" << components
    << "\" format=\"binary\">" << base64(&bytes, sizeof bytes) << base64(values.data(), bytes) << "</DataArray>\n";
}

void vec_array(std::ostream& f, const char* name, const std::vector<Vec3>& v) {
  std::vector<double> flat(3 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i) std::memcpy(&flat[3 * i], &v[i], 3 * sizeof(double));
  data_array(f, "Float64", name, 3, flat);
}

// The file's opening up to its <Piece>, with the time as field data (ParaView reads TimeValue
// as the data set's time; %.17g reads back as the same double).
void open_dataset(std::ostream& f, const char* type, double time) {
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
    << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<" << type
    << ">\n<FieldData>\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">"
    << std::setprecision(17) << time << "</DataArray>\n</FieldData>\n";
}

void close_dataset(std::ostream& f, const char* type) { f << "</Piece>\n</" << type << ">\n</VTKFile>\n"; }

// PolyData cells: <Lines> or <Polys> of `corners` consecutive points each.
void poly_cells(std::ostream& f, const char* kind, std::size_t cells, std::size_t corners) {
  std::vector<std::int64_t> connectivity(cells * corners), offsets(cells);
  for (std::size_t k = 0; k < connectivity.size(); ++k) connectivity[k] = static_cast<std::int64_t>(k);
  for (std::size_t c = 0; c < cells; ++c) offsets[c] = static_cast<std::int64_t>((c + 1) * corners);
  f << "<" << kind << ">\n";
  data_array(f, "Int64", "connectivity", 1, connectivity);
  data_array(f, "Int64", "offsets", 1, offsets);
  f << "</" << kind << ">\n";
}

// A PolyData piece of `cells` cells ("Lines" or "Polys"), each of `corners` consecutive
// points: the header, the points and the cells, up to the cell data.
void open_polydata(std::ostream& f, double time, const char* kind, std::size_t cells, std::size_t corners,
                   const std::vector<Vec3>& points) {
  open_dataset(f, "PolyData", time);
  f << "<Piece NumberOfPoints=\"" << cells * corners << "\" NumberOf" << kind << "=\"" << cells << "\">\n<Points>\n";
  vec_array(f, "position", points);
  f << "</Points>\n";
  poly_cells(f, kind, cells, corners);
}

}  // namespace

void write_vtu(const std::string& path, const Particles& p, double time) {
  const std::size_t n = p.size();
  // In the order of the ids, whatever the particles' numbering.
  const std::vector<std::size_t> order = p.in_id_order();
  const auto in_order = [&](const auto& array) {
    std::vector<std::decay_t<decltype(array[0])>> out(n);
    for (std::size_t k = 0; k < n; ++k) out[k] = array[order[k]];
    return out;
  };
  CheckedFile f(path);
  open_dataset(f, "UnstructuredGrid", time);
  f << "<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n<PointData Scalars=\"diameter\" Vectors=\"velocity\">\n";
  data_array(f, "Int64", "id", 1, in_order(p.id));
  data_array(f, "Int32", "material", 1, in_order(p.material));
  std::vector<double> diameter(n);
  for (std::size_t k = 0; k < n; ++k) diameter[k] = 2 * p.radius[order[k]];
  data_array(f, "Float64", "diameter", 1, diameter);
  vec_array(f, "velocity", in_order(p.velocity));
  vec_array(f, "angular_velocity", in_order(p.omega));
  vec_array(f, "force", in_order(p.force));
  data_array(f, "Int32", "contact_count", 1, in_order(p.contact_count));
  f << "</PointData>\n<Points>\n";
  vec_array(f, "position", in_order(p.position));
  f << "</Points>\n<Cells>\n";
  std::vector<std::int64_t> connectivity(n), offsets(n);
  std::vector<std::uint8_t> types(n, 1);  // VTK_VERTEX
  for (std::size_t i = 0; i < n; ++i) connectivity[i] = static_cast<std::int64_t>(i), offsets[i] = static_cast<std::int64_t>(i + 1);
  data_array(f, "Int64", "connectivity", 1, connectivity);
  data_array(f, "Int64", "offsets", 1, offsets);
  data_array(f, "UInt8", "types", 1, types);
  f << "</Cells>\n";
  close_dataset(f, "UnstructuredGrid");
  f.close();
}

void write_contacts_vtp(const std::string& path, const std::vector<NetworkContact>& contacts, double time, bool rolling) {
  const std::size_t n = contacts.size();
  std::vector<Vec3> points, point(n), branch(n), fn(n), ft(n), xi(n), spring(n);
  std::vector<std::int64_t> id_i(n), id_j(n);
  std::vector<std::int32_t> wall(n);
  std::vector<double> overlap(n), normal_history(2 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const NetworkContact& c = contacts[k];
    points.push_back(c.centre_i);
    points.push_back(c.centre_i + c.branch);
    id_i[k] = c.id_i, id_j[k] = c.id_j, wall[k] = c.wall;
    point[k] = c.point, branch[k] = c.branch, fn[k] = c.normal_force, ft[k] = c.tangential_force;
    overlap[k] = c.overlap, xi[k] = c.history.xi, spring[k] = c.history.rolling;
    normal_history[2 * k] = c.history.normal[0], normal_history[2 * k + 1] = c.history.normal[1];
  }
  CheckedFile f(path);
  open_polydata(f, time, "Lines", n, 2, points);
  f << "<CellData Vectors=\"normal_force\">\n";
  data_array(f, "Int64", "id_i", 1, id_i);
  data_array(f, "Int64", "id_j", 1, id_j);
  data_array(f, "Int32", "wall", 1, wall);
  vec_array(f, "contact_point", point);
  vec_array(f, "branch", branch);
  vec_array(f, "normal_force", fn);
  vec_array(f, "tangential_force", ft);
  data_array(f, "Float64", "overlap", 1, overlap);
  vec_array(f, "tangential_spring", xi);
  data_array(f, "Float64", "normal_history", 2, normal_history);
  if (rolling) vec_array(f, "rolling_spring", spring);
  f << "</CellData>\n";
  close_dataset(f, "PolyData");
  f.close();
}

namespace {

// The extent of the box's corners along the unit vector u, from `from`.
std::pair<double, double> box_extent(const Domain& domain, const Vec3& from, const Vec3& u) {
  double lo = INFINITY, hi = -INFINITY;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{c & 1 ? domain.upper.x : domain.lower.x, c & 2 ? domain.upper.y : domain.lower.y,
                      c & 4 ? domain.upper.z : domain.lower.z};
    lo = std::min(lo, dot(corner - from, u)), hi = std::max(hi, dot(corner - from, u));
  }
  return {lo, hi};
}

// A wall drawn as quadrilaterals over the box: a plane as one, the rectangle that covers
// the box seen along its normal (with a hole: kSides around the hole, out beyond the box); a
// cylinder as kSides facets around its axis, over the box's length along the axis; a cone as
// kSides facets from one rim to the other; a mesh as its triangles. Appends
// their corners and each one's normal (towards the particles).
void wall_quads(const Wall& w, const Domain& domain, std::vector<Vec3>& points, std::vector<Vec3>& normals) {
  constexpr int kSides = 48;
  // The unit vector at the angle of step k around the circle spanned by u and v.
  const auto around = [](const Vec3& u, const Vec3& v, double k) {
    const double a = 2 * M_PI * k / kSides;
    return std::cos(a) * u + std::sin(a) * v;
  };
  if (w.mesh) {  // each triangle as a quadrilateral with its last corner twice, where the mesh is now
    for (std::size_t t = 0; t < w.mesh->size(); ++t) {
      const auto& v = w.mesh->triangle(t);
      for (int k : {0, 1, 2, 2})  // from the mesh's frame (Wall::to_mesh) into the box's
        points.push_back(w.from_mesh(w.mesh->vertices()[v[static_cast<std::size_t>(k)]] - w.axis_offset) + w.axis_offset + w.point);
      normals.push_back(w.from_mesh(w.mesh->normal(t)));
    }
    return;
  }
  if (w.shape == WallShape::plane && w.hole_radius > 0) {  // a ring from the hole's rim to beyond the box
    const Vec3 u = perpendicular(w.normal), v = cross(w.normal, u);
    const double reach = norm(domain.upper - domain.lower) + norm(w.point - 0.5 * (domain.lower + domain.upper));
    for (int k = 0; k < kSides; ++k) {
      const Vec3 e0 = around(u, v, k), e1 = around(u, v, k + 1);
      for (const Vec3& r : {w.hole_radius * e0, w.hole_radius * e1, reach * e1, reach * e0}) points.push_back(w.point + r);
      normals.push_back(w.normal);
    }
    return;
  }
  if (w.shape == WallShape::plane) {
    const Vec3 u = perpendicular(w.normal), v = cross(w.normal, u);
    const auto [u0, u1] = box_extent(domain, w.point, u);
    const auto [v0, v1] = box_extent(domain, w.point, v);
    for (const auto& [a, b] : {std::pair{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}}) points.push_back(w.point + a * u + b * v);
    normals.push_back(w.normal);
    return;
  }
  const Vec3 u = perpendicular(w.axis), v = cross(w.axis, u);
  const bool cone = w.shape == WallShape::cone;
  const auto [s0, s1] = cone ? std::pair{0.0, w.length} : box_extent(domain, w.point, w.axis);
  const double radius1 = cone ? w.end_radius : w.radius;
  for (int k = 0; k < kSides; ++k) {
    const Vec3 e0 = around(u, v, k), e1 = around(u, v, k + 1);
    for (const auto& [r, s] : {std::pair{w.radius * e0, s0}, {w.radius * e1, s0}, {radius1 * e1, s1}, {radius1 * e0, s1}})
      points.push_back(w.point + r + s * w.axis);
    const Vec3 out = around(u, v, k + 0.5);
    normals.push_back(cone ? w.cone_normal(out) : w.inside ? -out : out);
  }
}

}  // namespace

void write_walls_vtp(const std::string& path, const std::vector<Wall>& walls, const Domain& domain, double time) {
  std::vector<Vec3> points, normal, velocity;
  std::vector<std::int32_t> index;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    wall_quads(walls[k], domain, points, normal);
    index.resize(normal.size(), static_cast<std::int32_t>(k));
    velocity.resize(normal.size(), walls[k].velocity);
  }
  CheckedFile f(path);
  open_polydata(f, time, "Polys", normal.size(), 4, points);
  f << "<CellData Normals=\"normal\">\n";
  data_array(f, "Int32", "wall", 1, index);
  vec_array(f, "normal", normal);
  vec_array(f, "velocity", velocity);
  f << "</CellData>\n";
  close_dataset(f, "PolyData");
  f.close();
}

void PvdIndex::add(double time, const std::string& file) {
  frames_.emplace_back(time, file);
  CheckedFile f(path_);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n<Collection>\n" << std::setprecision(17);
  for (const auto& [t, name] : frames_) f << "<DataSet timestep=\"" << t << "\" file=\"" << name << "\"/>\n";
  f << "</Collection>\n</VTKFile>\n";
  f.close();
}

}  // namespace tsubu
