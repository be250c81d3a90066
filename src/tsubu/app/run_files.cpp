#include "tsubu/app/run_files.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <stdexcept>
#include <unordered_map>

#include "tsubu/scenario/result_names.hpp"

namespace tsubu {

namespace fs = std::filesystem;

namespace {

// A file continued by a resume: cut back to its size at the checkpoint, then appended to.
void reopen(CheckedFile& f, const fs::path& path, std::uint64_t bytes) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec || size < bytes)
    throw std::runtime_error(path.string() + " is missing or shorter than at the checkpoint (" + std::to_string(bytes) +
                             " bytes): cannot continue it");
  fs::resize_file(path, bytes);
  f.open(path, CheckedFile::Mode::append);
}

// A table of full-precision rows: opened fresh with its header, or for a resume continued
// from its size at the checkpoint (`bytes`).
void open_table(CheckedFile& f, const fs::path& path, std::optional<std::uint64_t> bytes, const char* header) {
  if (bytes) {
    reopen(f, path, *bytes);
  } else {
    f.open(path);
    f << header;
  }
  f << std::setprecision(17);
}

// The data rows of a CSV file: its lines after the header.
std::size_t data_rows(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const auto lines = std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
  return lines > 0 ? static_cast<std::size_t>(lines - 1) : 0;
}

}  // namespace

RunFiles::RunFiles(const Scenario& sc, const Simulation& sim, const fs::path& out_dir,
                   const std::vector<std::string>& analyses, const Checkpoint* from)
    : sc_(sc),
      series_path_(out_dir / "series.csv"),
      track_path_(out_dir / "track.csv"),
      outflow_path_(out_dir / "outflow.csv"),
      frames_(out_dir, sc.output.contacts, !sim.world().walls.empty()) {
  for (std::size_t k = 0; k < sc.walls.size(); ++k)
    if (!sc.walls[k].motion.empty()) moving_walls_.push_back(k);
  if (from) {
    reopen(series_, series_path_, from->output.series_bytes);
  } else {
    series_.open(series_path_);
    const std::vector<std::string> columns = series_columns(sc);
    for (std::size_t k = 0; k < columns.size(); ++k) series_ << (k > 0 ? "," : "") << columns[k];
    for (const std::string& name : analyses) series_ << ',' << name;
    series_ << '\n';
  }
  series_ << std::setprecision(12);
  for (const AnalysisSpec& a : sc.analyses)
    if (a.kind == AnalysisSpec::Kind::profiles)
      profiles_.emplace(a, out_dir / "profiles", from ? std::optional(data_rows(series_path_)) : std::nullopt);
  if (from) frames_.restore(from->output.pvd);
  if (!sc.output.track.empty())
    open_table(track_, track_path_, from ? std::optional(from->output.track_bytes) : std::nullopt,
               "time,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,contacts\n");
  if (sim.outflow())
    open_table(outflow_, outflow_path_, from ? std::optional(from->output.outflow_bytes) : std::nullopt,
               "time,id,face,diameter,mass,x,y,z,vx,vy,vz\n");
}

void RunFiles::series_row(const Simulation& sim, const Energies& e, const ContactTotals& c,
                          const std::vector<double>& analyses) {
  const World& world = sim.world();
  series_ << world.time << ',' << e.kinetic_translational << ',' << e.kinetic_rotational << ',' << e.potential_gravity
          << ',' << c.elastic_energy << ',' << c.contacts << ',' << c.max_overlap_ratio;
  for (std::size_t k : moving_walls_) {  // a plane: along its normal; a mesh: the distance it has moved
    const Wall& w = world.walls[k];
    const Vec3 moved = w.point - sc_.walls[k].point;
    series_ << ',' << (w.mesh ? norm(moved) : dot(moved, w.normal)) << ',' << sim.forces().wall_load(world, k);
  }
  if (sim.block())  // particles per level (step dt/2^k)
    for (std::size_t n : sim.block()->level_histogram()) series_ << ',' << n;
  if (sim.inflow()) series_ << ',' << world.particles.size() << ',' << sim.inflow_mass_entered();
  if (const Outflow* outflow = sim.outflow()) series_ << ',' << outflow->totals().count << ',' << outflow->totals().mass;
  for (double v : analyses) series_ << ',' << v;
  series_ << '\n';
  if (profiles_) profiles_->write(world);
}

void RunFiles::track_rows(const World& world) {
  if (!track_.is_open()) return;
  // Where each tracked grain is now (spatial sorting moves grains between indices): one pass.
  const Particles& p = world.particles;
  std::unordered_map<std::int64_t, std::size_t> index_of;
  for (std::int64_t id : sc_.output.track) index_of.emplace(id, p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    if (auto it = index_of.find(p.id[i]); it != index_of.end()) it->second = i;
  for (std::int64_t id : sc_.output.track) {
    const std::size_t i = index_of.at(id);
    if (i == p.size()) continue;  // an inflow grain not yet entered
    const Vec3 &x = p.position[i], &v = p.velocity[i], &w = p.omega[i], &f = p.force[i];
    track_ << world.time << ',' << p.id[i] << ',' << x.x << ',' << x.y << ',' << x.z << ',' << v.x << ',' << v.y << ','
           << v.z << ',' << w.x << ',' << w.y << ',' << w.z << ',' << f.x << ',' << f.y << ',' << f.z << ','
           << p.contact_count[i] << '\n';
  }
}

void RunFiles::departure_rows(const std::vector<Departure>& departures) {
  for (const Departure& d : departures) {
    const Vec3 &x = d.position, &v = d.velocity;
    outflow_ << d.time << ',' << d.id << ',' << kBoxFaces[static_cast<std::size_t>(d.face)] << ',' << d.diameter << ',' << d.mass << ',' << x.x
             << ',' << x.y << ',' << x.z << ',' << v.x << ',' << v.y << ',' << v.z << '\n';
  }
}

void RunFiles::flush() {
  series_.flush();
  if (track_.is_open()) track_.flush();
  if (outflow_.is_open()) outflow_.flush();
  if (profiles_) profiles_->flush();
}

void RunFiles::sync() {
  sync_file(series_path_);
  if (track_.is_open()) sync_file(track_path_);
  if (outflow_.is_open()) sync_file(outflow_path_);
  if (profiles_)
    for (const fs::path& f : profiles_->paths()) sync_file(f);
  for (const auto& f : frames_.unsynced()) sync_file(f);
  frames_.mark_synced();
}

OutputState RunFiles::state() const {
  OutputState s;
  s.frame = frames_.count();
  s.pvd = frames_.frames();
  s.series_bytes = fs::file_size(series_path_);
  s.track_bytes = track_.is_open() ? fs::file_size(track_path_) : 0;
  s.outflow_bytes = outflow_.is_open() ? fs::file_size(outflow_path_) : 0;
  return s;
}

void RunFiles::close() {
  series_.close();
  track_.close();
  outflow_.close();
  if (profiles_) profiles_->close();
}

}  // namespace tsubu
