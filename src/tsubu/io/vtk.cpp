#include "tsubu/io/vtk.hpp"

#include <cstdint>
#include <cstring>
#include <iomanip>

#include "tsubu/io/checked_file.hpp"

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

}  // namespace

void write_vtu(const std::string& path, const Particles& p) {
  const std::size_t n = p.size();
  CheckedFile f(path);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
    << n << "\" NumberOfCells=\"" << n << "\">\n<PointData Scalars=\"diameter\" Vectors=\"velocity\">\n";
  data_array(f, "Int64", "id", 1, p.id);
  std::vector<double> diameter(n);
  for (std::size_t i = 0; i < n; ++i) diameter[i] = 2 * p.radius[i];
  data_array(f, "Float64", "diameter", 1, diameter);
  vec_array(f, "velocity", p.velocity);
  vec_array(f, "angular_velocity", p.omega);
  vec_array(f, "force", p.force);
  data_array(f, "Int32", "contact_count", 1, p.contact_count);
  f << "</PointData>\n<Points>\n";
  vec_array(f, "position", p.position);
  f << "</Points>\n<Cells>\n";
  std::vector<std::int64_t> connectivity(n), offsets(n);
  std::vector<std::uint8_t> types(n, 1);  // VTK_VERTEX
  for (std::size_t i = 0; i < n; ++i) connectivity[i] = static_cast<std::int64_t>(i), offsets[i] = static_cast<std::int64_t>(i + 1);
  data_array(f, "Int64", "connectivity", 1, connectivity);
  data_array(f, "Int64", "offsets", 1, offsets);
  data_array(f, "UInt8", "types", 1, types);
  f << "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
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
