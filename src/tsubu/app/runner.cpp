#include "tsubu/app/runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <unistd.h>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/io/vtk.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/version.hpp"

namespace tsubu {

namespace {

std::int64_t every(double interval, double dt) {
  return std::max<std::int64_t>(1, std::llround(interval / dt));
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (c == '\n') out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) out += ' ';
    else out += c;
  }
  return out;
}

void write_run_json(const std::string& path, const Scenario& sc, int threads, const RunSummary& s,
                    const std::string& status, const std::string& message) {
  std::ofstream f(path);
  f << std::setprecision(17);
  const double ps = s.wall_seconds > 0 ? static_cast<double>(s.particles) * static_cast<double>(s.steps) / s.wall_seconds : 0;
  f << "{\n  \"engine\": \"tsubu\",\n  \"version\": \"" << kVersion << "\",\n  \"scenario\": \"" << json_escape(sc.file)
    << "\",\n  \"name\": \"" << json_escape(sc.name) << "\",\n  \"scenario_hash\": \"" << std::hex << sc.hash << std::dec
    << "\",\n  \"status\": \"" << status << "\",\n  \"message\": \"" << json_escape(message) << "\",\n  \"threads\": "
    << threads << ",\n  \"dt\": " << sc.dt << ",\n  \"steps\": " << s.steps << ",\n  \"particles\": " << s.particles
    << ",\n  \"contact_evaluations\": " << s.contact_evaluations << ",\n  \"wall_time_s\": " << s.wall_seconds
    << ",\n  \"particle_steps_per_second\": " << ps << ",\n  \"domain\": {\"lower\": [" << sc.domain.lower.x << ", "
    << sc.domain.lower.y << ", " << sc.domain.lower.z << "], \"upper\": [" << sc.domain.upper.x << ", " << sc.domain.upper.y
    << ", " << sc.domain.upper.z << "]},\n  \"results\": {";
  const char* sep = "\n";
  for (const auto& [k, v] : s.results) {
    f << sep << "    \"" << json_escape(k) << "\": " << std::setprecision(17) << v;
    sep = ",\n";
  }
  f << (s.results.empty() ? "}" : "\n  }") << "\n}\n";
}

}  // namespace

RunSummary run_scenario(const Scenario& sc, const std::string& out_dir, int threads, bool progress) {
  namespace fs = std::filesystem;
  fs::create_directories(fs::path(out_dir) / "vtk");
  World world = build_world(sc);
  ForceField forces;
  RunSummary summary;
  summary.particles = world.particles.size();

  std::ofstream series(fs::path(out_dir) / "series.csv");
  // Moving walls add two columns each: the displacement of the plane along its normal and
  // the load the particles put on it.
  std::vector<std::size_t> moving;
  for (std::size_t k = 0; k < world.walls.size(); ++k)
    if (!world.walls[k].motion.empty()) moving.push_back(k);
  const std::vector<Vec3> wall_start = [&] {
    std::vector<Vec3> v;
    for (const Wall& w : world.walls) v.push_back(w.point);
    return v;
  }();
  series << "time,kinetic_translational,kinetic_rotational,potential_gravity,elastic,contacts,max_overlap_ratio";
  for (std::size_t k : moving) series << ",wall" << k << "_displacement,wall" << k << "_load";
  series << '\n' << std::setprecision(12);
  PvdIndex pvd((fs::path(out_dir) / "vtk" / "particles.pvd").string());
  std::vector<std::size_t> tracked;  // indices of the tracked particle ids
  for (std::int64_t id : sc.output.track) {
    const auto it = std::find(world.particles.id.begin(), world.particles.id.end(), id);
    if (it == world.particles.id.end())
      throw InputError(sc.output.where.file, sc.output.where.line, sc.output.where.key,
                       "no particle has id " + std::to_string(id) + "; ids run from 0 to " +
                           std::to_string(static_cast<long>(world.particles.size()) - 1) + " in the order of [[particles]]");
    tracked.push_back(static_cast<std::size_t>(it - world.particles.id.begin()));
  }
  std::ofstream track;
  if (!tracked.empty()) {
    track.open(fs::path(out_dir) / "track.csv");
    track << "time,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,contacts\n" << std::setprecision(17);
  }
  auto write_track = [&] {
    const Particles& p = world.particles;
    for (std::size_t i : tracked) {
      const Vec3 &x = p.position[i], &v = p.velocity[i], &w = p.omega[i], &f = p.force[i];
      track << world.time << ',' << p.id[i] << ',' << x.x << ',' << x.y << ',' << x.z << ',' << v.x << ',' << v.y << ','
            << v.z << ',' << w.x << ',' << w.y << ',' << w.z << ',' << f.x << ',' << f.y << ',' << f.z << ','
            << p.contact_count[i] << '\n';
    }
  };
  int frame = 0;
  auto write_series = [&] {
    const Energies e = energies(world);
    const ContactTotals c = forces.totals(world);
    series << world.time << ',' << e.kinetic_translational << ',' << e.kinetic_rotational << ',' << e.potential_gravity
           << ',' << c.elastic_energy << ',' << c.contacts << ',' << c.max_overlap_ratio;
    for (std::size_t k : moving)
      series << ',' << dot(world.walls[k].point - wall_start[k], world.walls[k].normal) << ','
             << forces.wall_load(world, k);
    series << '\n';
  };
  auto write_frame = [&] {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.vtu", frame++);
    write_vtu((fs::path(out_dir) / "vtk" / name).string(), world.particles);
    pvd.add(world.time, name);
  };

  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  const std::int64_t series_every = every(sc.output.series_interval, sc.dt);
  const std::int64_t vtk_every = sc.output.vtk_interval > 0 ? every(sc.output.vtk_interval, sc.dt) : 0;
  const std::int64_t track_every = every(sc.output.track_interval, sc.dt);
  const bool show_progress = progress && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  double next_progress = 0.5;

  const std::string json = (fs::path(out_dir) / "run.json").string();
  try {
    forces.compute(world);
    write_series();
    write_track();
    if (vtk_every) write_frame();
    for (std::int64_t s = 1; s <= steps; ++s) {
      advance(sc.integrator, world, forces);
      if (s % series_every == 0 || s == steps) write_series();
      if (s % track_every == 0 || s == steps) write_track();
      if (vtk_every && (s % vtk_every == 0 || s == steps)) write_frame();
      if (show_progress && elapsed() > next_progress) {
        next_progress = elapsed() + 0.5;
        const double rate = static_cast<double>(s) / elapsed();
        std::fprintf(stderr, "\r t = %.4g s  %5.1f%%  %.3g steps/s  ETA %.0f s   ", world.time, 100.0 * static_cast<double>(s) / static_cast<double>(steps), rate,
                     static_cast<double>(steps - s) / rate);
      }
    }
  } catch (const NumericalError& e) {
    summary.steps = world.step;
    summary.wall_seconds = elapsed();
    summary.contact_evaluations = forces.evaluations();
    series.flush();
    write_frame();
    write_run_json(json, sc, threads, summary, "failed", e.what());
    throw;
  }
  if (show_progress) std::fprintf(stderr, "\n");
  summary.steps = world.step;
  summary.wall_seconds = elapsed();
  summary.contact_evaluations = forces.evaluations();
  for (const auto& a : sc.analyses) {
    if (a.kind == AnalysisSpec::Kind::solid_fraction) {
      summary.results[a.name] = solid_fraction(world, a.z_low, a.z_high);
    } else {
      summary.results[a.name] = coordination(world, a.z_low, a.z_high, false);
      summary.results[a.name + "_no_rattlers"] = coordination(world, a.z_low, a.z_high, true);
    }
  }
  write_run_json(json, sc, threads, summary, "ok", "");
  return summary;
}

}  // namespace tsubu
