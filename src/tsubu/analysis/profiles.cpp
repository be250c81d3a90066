#include "tsubu/analysis/profiles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/core/exact_sum.hpp"

namespace tsubu {

namespace {

std::size_t size_class(const std::vector<double>& edges, double d) {
  const auto above = std::upper_bound(edges.begin(), edges.end(), d) - edges.begin();  // first edge > d
  return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(above - 1, 0, static_cast<std::ptrdiff_t>(edges.size()) - 2));
}

}  // namespace

Profiles measure_profiles(const AnalysisSpec& a, const World& w) {
  const Particles& p = w.particles;
  const std::size_t n = static_cast<std::size_t>(a.profile_slices), classes = a.class_edges.size() - 1;
  const double thickness = (a.z_high - a.z_low) / static_cast<double>(n);
  auto bound = [&](std::size_t k) { return a.z_low + (a.z_high - a.z_low) * static_cast<double>(k) / static_cast<double>(n); };
  Profiles out;
  out.grains.assign(n, 0);
  std::vector<std::vector<ExactSum>> class_volume(classes, std::vector<ExactSum>(n));
  std::vector<double> contacts(n, 0.0);  // integers: exact in any order
  std::vector<std::array<ExactSum, 3>> momentum_sum(n);
  std::vector<std::vector<SizedGrain>> grains(n);
  const std::vector<int> z = pair_contact_counts(w);
  // The slice holding height x (clamped to the range's ends).
  auto slice_of = [&](double x) {
    return static_cast<std::size_t>(std::clamp(std::floor((x - a.z_low) / thickness), 0.0, static_cast<double>(n - 1)));
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = p.position[i].z, r = p.radius[i];
    if (x + r <= a.z_low || x - r >= a.z_high) continue;
    std::vector<ExactSum>& volume = class_volume[size_class(a.class_edges, 2 * r)];
    for (std::size_t k = slice_of(x - r), last = slice_of(x + r); k <= last; ++k)
      volume[k] += sphere_slab_volume(x, r, bound(k), bound(k + 1));
    if (!(x > a.z_low && x < a.z_high)) continue;
    const std::size_t k = slice_of(x);
    ++out.grains[k];
    contacts[k] += z[i];
    for (int c = 0; c < 3; ++c) momentum_sum[k][static_cast<std::size_t>(c)] += p.velocity[i][c];
    grains[k].push_back({2 * r, p.mass[i]});
  }
  const double area = w.domain.length(0) * w.domain.length(1), nan = std::numeric_limits<double>::quiet_NaN();
  out.velocity.assign(n, Vec3{nan, nan, nan});
  out.temperature.assign(n, nan);
  out.coordination.assign(n, nan);
  out.class_fraction.assign(classes, std::vector<double>(n, 0.0));
  for (std::size_t c = 0; c < classes; ++c)
    for (std::size_t k = 0; k < n; ++k) out.class_fraction[c][k] = class_volume[c][k].value();
  for (std::size_t k = 0; k < n; ++k) {
    out.centre.push_back(0.5 * (bound(k) + bound(k + 1)));
    double solid = 0;
    for (std::vector<double>& volume : out.class_fraction) {
      volume[k] /= area * (bound(k + 1) - bound(k));
      solid += volume[k];
    }
    out.solid_fraction.push_back(solid);
    out.sizes.push_back(mass_percentiles(grains[k]));
    if (out.grains[k] == 0) continue;
    const double count = static_cast<double>(out.grains[k]);
    out.coordination[k] = contacts[k] / count;
    out.velocity[k] = Vec3{momentum_sum[k][0].value(), momentum_sum[k][1].value(), momentum_sum[k][2].value()} / count;
  }
  // Fluctuations about the slice means: a second pass, free of the cancellation of
  // mean |v|^2 - |mean v|^2.
  std::vector<ExactSum> fluctuation(n);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = p.position[i].z;
    if (!(x > a.z_low && x < a.z_high)) continue;
    const std::size_t k = slice_of(x);
    fluctuation[k] += norm2(p.velocity[i] - out.velocity[k]);
  }
  for (std::size_t k = 0; k < n; ++k)
    if (out.grains[k] > 0) out.temperature[k] = fluctuation[k].value() / (3 * static_cast<double>(out.grains[k]));
  return out;
}

namespace {

// The files, in the order ProfileWriter::write fills them: name and the header's words.
std::vector<std::pair<std::string, std::string>> quantities(const AnalysisSpec& a) {
  std::vector<std::pair<std::string, std::string>> q = {
      {"solid_fraction", "solid fraction [-]"},
      {"grains", "grains with their centre in the slice [-]"},
      {"coordination", "mean coordination number [-]"},
      {"velocity_x", "mean velocity x [m/s]"},
      {"velocity_y", "mean velocity y [m/s]"},
      {"velocity_z", "mean velocity z [m/s]"},
      {"granular_temperature", "granular temperature (1/3) mean |v - mean v|^2 [m^2/s^2]"},
      {"d10", "D10 by mass [m]"},
      {"d50", "D50 by mass [m]"},
      {"d90", "D90 by mass [m]"}};
  for (std::size_t c = 0; c + 1 < a.class_edges.size(); ++c) {
    std::ostringstream words;
    words << std::setprecision(6) << "volume fraction of size class " << c << " (" << a.class_edges[c] << " <= d < "
          << a.class_edges[c + 1] << " m) [-]";
    q.emplace_back("volume_fraction_class" + std::to_string(c), words.str());
  }
  return q;
}

// Cuts the file back to its header and `rows` rows.
void keep_rows(const std::filesystem::path& path, std::size_t rows) {
  std::ifstream in(path, std::ios::binary);
  std::uintmax_t bytes = 0;
  std::size_t lines = 0;
  for (char c; lines < rows + 1 && in.get(c);) {
    ++bytes;
    if (c == '\n') ++lines;
  }
  if (lines < rows + 1)
    throw std::runtime_error(path.string() + " is missing or holds fewer rows than series.csv at the checkpoint (" +
                             std::to_string(rows) + "): cannot continue it");
  std::filesystem::resize_file(path, bytes);
}

}  // namespace

ProfileWriter::ProfileWriter(const AnalysisSpec& a, const std::filesystem::path& folder, std::optional<std::size_t> rows)
    : spec_(a) {
  std::filesystem::create_directories(folder);
  std::vector<double> centres = measure_profiles(a, World{}).centre;  // no grains: cheap
  for (const auto& [name, words] : quantities(a)) {
    Column c{folder / (name + ".csv"), std::make_unique<CheckedFile>()};
    if (rows) {
      keep_rows(c.path, *rows);
      c.file->open(c.path, CheckedFile::Mode::append);
    } else {
      c.file->open(c.path);
      *c.file << "time [s]; " << words << " at slice centre z [m]" << std::setprecision(9);
      for (double z : centres) *c.file << ',' << z;
      *c.file << '\n';
    }
    *c.file << std::setprecision(12);
    files_.push_back(std::move(c));
  }
}

void ProfileWriter::write(const World& w) {
  const Profiles p = measure_profiles(spec_, w);
  std::size_t f = 0;
  auto row = [&](auto value) {
    CheckedFile& out = *files_[f++].file;
    out << w.time;
    for (std::size_t k = 0; k < p.centre.size(); ++k) out << ',' << value(k);
    out << '\n';
  };
  row([&](std::size_t k) { return p.solid_fraction[k]; });
  row([&](std::size_t k) { return p.grains[k]; });
  row([&](std::size_t k) { return p.coordination[k]; });
  for (int axis = 0; axis < 3; ++axis) row([&](std::size_t k) { return p.velocity[k][axis]; });
  row([&](std::size_t k) { return p.temperature[k]; });
  row([&](std::size_t k) { return p.sizes[k].d10; });
  row([&](std::size_t k) { return p.sizes[k].d50; });
  row([&](std::size_t k) { return p.sizes[k].d90; });
  for (const std::vector<double>& fraction : p.class_fraction) row([&](std::size_t k) { return fraction[k]; });
}

void ProfileWriter::flush() {
  for (Column& c : files_) c.file->flush();
}

void ProfileWriter::close() {
  for (Column& c : files_) c.file->close();
}

std::vector<std::filesystem::path> ProfileWriter::paths() const {
  std::vector<std::filesystem::path> out;
  for (const Column& c : files_) out.push_back(c.path);
  return out;
}

}  // namespace tsubu
