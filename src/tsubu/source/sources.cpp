#include "tsubu/source/sources.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <unistd.h>

#include "tsubu/core/error.hpp"
#include "tsubu/search/sphere_grid.hpp"

namespace tsubu {

namespace {
const char* const kColumns[] = {"x", "y", "z", "d", "vx", "vy", "vz"};  // the key named by a bad field
}  // namespace

std::size_t particle_limit() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::size_t(1) << 32;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) / kBytesPerParticle;
}

namespace {

std::string too_many(double count) {
  const std::size_t limit = particle_limit();
  std::ostringstream s;
  s << std::setprecision(3) << "would create ";
  if (count > 0) s << count;
  else s << "more than " << limit;
  s << " particles; this machine holds at most " << limit << " (about " << kBytesPerParticle / 1024
    << " KiB each with their contacts, " << static_cast<double>(limit) * kBytesPerParticle / (1024.0 * 1024 * 1024)
    << " GiB of memory)";
  return s.str();
}

}  // namespace

std::vector<Grain> read_csv_grains(const ParticleSource& src) {
  std::ifstream in(src.file);
  if (!in) throw InputError(src.at("file"), "cannot open \"" + src.file + "\"");
  return parse_csv_grains(in, src.file);
}

namespace {

// The rows of a CSV particle file: each data line's numbers, with its line number. As
// spreadsheets write it: a UTF-8 byte-order mark, CRLF line ends, tabs between fields (in a
// line without commas), spaces around them, a leading '+'. Blank lines and lines starting
// with '#' are skipped, and so is a header: a line before the first row whose first field
// starts with `header`'s first letter (either case). A field that is not a finite number is
// an error naming the column (`columns`, in order) and the format `rows`.
template <class Row>
void for_each_csv_row(std::istream& in, const std::string& name, const std::vector<const char*>& columns,
                      const std::string& rows, Row&& row) {
  std::string line;
  long number = 0;
  bool any = false;
  const char header = columns.front()[0];
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find(',') == std::string::npos) std::replace(line.begin(), line.end(), '\t', ',');
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    if (!any && std::tolower(static_cast<unsigned char>(line[first])) == header) continue;
    std::vector<double> v;
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = line.find(',', start);
      std::string_view field(line.data() + start, (comma == std::string::npos ? line.size() : comma) - start);
      while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.remove_prefix(1);
      while (!field.empty() && (field.back() == ' ' || field.back() == '\t')) field.remove_suffix(1);
      if (field.size() > 1 && field[0] == '+' && field[1] != '-' && field[1] != '+') field.remove_prefix(1);  // from_chars refuses '+'
      double x = 0;
      const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), x);
      if (ec != std::errc() || ptr != field.data() + field.size() || !std::isfinite(x))
        throw InputError(name, number, v.size() < columns.size() ? columns[v.size()] : "",
                         "\"" + std::string(field) + "\" is not a finite number; rows are " + rows);
      v.push_back(x);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    any = true;
    row(v, number);
  }
  if (!any) throw InputError(name, number, "", "no particles in the file");
}

}  // namespace

std::vector<Grain> parse_csv_grains(std::istream& in, const std::string& name) {
  std::vector<Grain> out;
  const std::vector<const char*> columns(std::begin(kColumns), std::end(kColumns));
  for_each_csv_row(in, name, columns, "x,y,z,d[,vx,vy,vz] in SI units", [&](const std::vector<double>& v, long number) {
    if (v.size() != 4 && v.size() != 7)
      throw InputError(name, number, "", "expected 4 or 7 numbers (x,y,z,d[,vx,vy,vz]), got " + std::to_string(v.size()));
    if (!(v[3] > 0)) throw InputError(name, number, "d", "the diameter must be > 0 (metres)");
    Grain g{{v[0], v[1], v[2]}, {}, v[3], {name, number, ""}, {}, -1};
    if (v.size() == 7) g.velocity = {v[4], v[5], v[6]};
    out.push_back(g);
    if (out.size() > particle_limit()) throw InputError(name, number, "", too_many(0));
  });
  return out;
}

std::vector<Grain> read_state_grains(const ParticleSource& src, std::size_t materials) {
  std::ifstream in(src.file);
  if (!in) throw InputError(src.at("file"), "cannot open \"" + src.file + "\"");
  return parse_state_grains(in, src.file, materials);
}

std::vector<Grain> parse_state_grains(std::istream& in, const std::string& name, std::size_t materials) {
  std::vector<Grain> out;
  const std::vector<const char*> columns = {"id", "material", "radius", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"};
  const std::string rows = "id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz in SI units, as tsubu export writes them";
  for_each_csv_row(in, name, columns, rows, [&](const std::vector<double>& v, long number) {
    if (v.size() != columns.size())
      throw InputError(name, number, "", "expected 12 numbers, got " + std::to_string(v.size()) + "; rows are " + rows);
    if (v[0] != std::floor(v[0])) throw InputError(name, number, "id", "must be an integer");
    if (!(v[1] >= 0 && v[1] < static_cast<double>(materials) && v[1] == std::floor(v[1])))
      throw InputError(name, number, "material",
                       "must be the index of one of the scenario's " + std::to_string(materials) +
                           " [[materials]] (0 to " + std::to_string(materials - 1) + ", in the order of the file)");
    if (!(v[2] > 0)) throw InputError(name, number, "radius", "the radius must be > 0 (metres)");
    const Grain g{{v[3], v[4], v[5]}, {v[6], v[7], v[8]}, 2 * v[2], {name, number, ""}, {v[9], v[10], v[11]}, static_cast<int>(v[1])};
    out.push_back(g);
    if (out.size() > particle_limit()) throw InputError(name, number, "", too_many(0));
  });
  return out;
}

std::vector<Grain> lattice_grains(const ParticleSource& src) {
  std::vector<Grain> out;
  const double r = 0.5 * src.diameter;
  double per_axis[3], total = 1;
  for (int k = 0; k < 3; ++k) {
    per_axis[k] = std::floor((src.upper[k] - src.lower[k] - src.diameter) / src.spacing + 1e-9) + 1;
    if (per_axis[k] < 1)
      throw InputError(src.where, "the region is smaller than one diameter");
    total *= per_axis[k];
  }
  if (total > static_cast<double>(particle_limit()))
    throw InputError(src.at("spacing"), too_many(total));
  const int count[3] = {static_cast<int>(per_axis[0]), static_cast<int>(per_axis[1]), static_cast<int>(per_axis[2])};
  for (int k = 0; k < count[2]; ++k)
    for (int j = 0; j < count[1]; ++j)
      for (int i = 0; i < count[0]; ++i)
        out.push_back({src.lower + Vec3{r + i * src.spacing, r + j * src.spacing, r + k * src.spacing}, src.velocity,
                       src.diameter, src.where, {}, -1});
  return out;
}

std::vector<Grain> random_grains(const ParticleSource& src, const Domain& domain, Random& rng) {
  Vec3 size = src.upper - src.lower;
  const double target = src.solid_fraction * size.x * size.y * size.z;
  std::vector<double> diameters;
  const std::size_t limit = particle_limit();
  for (double volume = 0; volume < target;) {
    const double d = src.sizes.sample(rng);
    if (!(d > 0 && std::isnormal(d * d * d))) {  // NaN, 0, infinite, or a volume lost to underflow
      std::ostringstream s;
      s << "drew the diameter " << d << " m: these parameters give diameters that cannot be simulated "
        << "(they must be finite and > 0, in metres; a talbot exponent far from 0 to 6 overflows)";
      throw InputError(src.at("distribution"), s.str());
    }
    diameters.push_back(d);
    volume += M_PI / 6 * d * d * d;
    if (diameters.size() > limit)
      throw InputError(src.at("solid_fraction"),
                       too_many(target / (volume / static_cast<double>(diameters.size()))));
  }
  std::sort(diameters.rbegin(), diameters.rend());
  std::array<bool, 3> wrap;
  for (int k = 0; k < 3; ++k)
    wrap[k] = domain.periodic[k] && src.lower[k] == domain.lower[k] && src.upper[k] == domain.upper[k];
  SphereGrid placed_grains(domain, src.lower, src.upper, wrap, diameters.front());
  std::vector<Grain> out;
  for (std::size_t n = 0; n < diameters.size(); ++n) {
    const double d = diameters[n], r = 0.5 * d;
    bool placed = false;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      Vec3 x;
      for (int k = 0; k < 3; ++k)
        x[k] = wrap[k] ? rng.uniform(src.lower[k], src.upper[k]) : rng.uniform(src.lower[k] + r, src.upper[k] - r);
      if (placed_grains.overlaps(x, r)) continue;
      placed_grains.add(x, r);
      out.push_back({x, src.velocity, d, src.where, {}, -1});
      placed = true;
    }
    if (!placed)
      throw InputError(src.at("solid_fraction"),
                       "could not place grain " + std::to_string(n + 1) + " of " + std::to_string(diameters.size()) +
                           " without overlap; lower the solid fraction or enlarge the region");
  }
  return out;
}

}  // namespace tsubu
