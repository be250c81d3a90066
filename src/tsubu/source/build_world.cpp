#include "tsubu/source/build_world.hpp"

#include <algorithm>
#include <numeric>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/source/sources.hpp"

namespace tsubu {

namespace {

[[noreturn]] void fail_at(const SourceLocation& at, const std::string& what) {
  throw InputError(at.file, at.line, at.key, what);
}

std::string format_vec(const Vec3& x) {
  std::ostringstream s;
  s << "(" << x.x << ", " << x.y << ", " << x.z << ")";
  return s.str();
}

LawTable build_laws(const Scenario& sc) {
  LawTable table;
  table.n_materials = static_cast<int>(sc.materials.size());
  for (int a = 0; a < table.n_materials; ++a)
    for (int b = 0; b < table.n_materials; ++b) {
      ContactSpec spec = sc.default_contact;
      for (const auto& pc : sc.pair_contacts)
        if ((pc.a == a && pc.b == b) || (pc.a == b && pc.b == a)) spec = pc.spec;
      table.laws.push_back(make_pair_law(spec, sc.materials[static_cast<std::size_t>(a)], sc.materials[static_cast<std::size_t>(b)]));
    }
  return table;
}

// Overlapping input particles beyond each source's tolerance are an input error naming both.
void check_overlaps(const World& w, const std::vector<Grain>& grains, const std::vector<double>& tolerance) {
  CellGrid grid;
  std::vector<Pair> pairs;
  grid.find_pairs(w.particles, w.domain, 0.0, pairs);
  const Particles& p = w.particles;
  for (const Pair& pr : pairs) {
    const double dist = norm(w.domain.separation(p.position[pr.i], p.position[pr.j]));
    const double overlap = p.radius[pr.i] + p.radius[pr.j] - dist;
    const double ratio = overlap / (2 * std::min(p.radius[pr.i], p.radius[pr.j]));
    if (ratio > std::min(tolerance[pr.i], tolerance[pr.j])) {
      const Grain& a = grains[std::max(pr.i, pr.j)];  // the later grain, naming the earlier one
      const Grain& b = grains[std::min(pr.i, pr.j)];
      std::ostringstream s;
      s << "particle overlaps the one from " << b.where.file << ":" << b.where.line << " by " << ratio
        << " of the smaller diameter; allowed up to " << std::min(tolerance[pr.i], tolerance[pr.j])
        << " (overlap_tolerance of csv sources; lattice and random particles may only touch)";
      fail_at(a.where, s.str());
    }
  }
}

}  // namespace

InflowColumn inflow_column(const Scenario& sc, const ParticleSource& src) {
  InflowColumn c;
  c.x_low = sc.domain.lower.x;
  c.y_low = sc.domain.lower.y;
  c.length_x = sc.domain.length(0);
  c.length_y = sc.domain.length(1);
  c.entry_height = src.entry_height;
  c.speed = src.fall_speed;
  c.solid_fraction = src.solid_fraction;
  c.sizes = src.sizes;
  c.density = sc.materials[static_cast<std::size_t>(src.material)].density;
  c.mass_limit = src.mass_limit;
  c.omega_star_rms = src.omega_star_rms;
  c.gravity = norm(sc.gravity);
  return c;
}

const ParticleSource* inflow_source(const Scenario& sc) {
  for (const ParticleSource& src : sc.sources)
    if (src.kind == ParticleSource::Kind::inflow) return &src;
  return nullptr;
}

World build_empty_world(const Scenario& sc) {
  World w;
  w.domain = sc.domain;
  w.materials = sc.materials;
  w.walls = sc.walls;
  w.gravity = sc.gravity;
  w.fluid = sc.fluid;
  w.dt = sc.dt;
  w.overlap_limit = sc.overlap_limit;
  w.skin = sc.skin;
  w.search = sc.search;
  w.laws = build_laws(sc);
  return w;
}

World build_world(const Scenario& sc) {
  World w = build_empty_world(sc);
  Random rng(sc.seed);
  std::vector<Grain> grains;
  std::vector<double> tolerance;
  for (const auto& src : sc.sources) {
    if (src.kind == ParticleSource::Kind::inflow) continue;  // its grains arrive during the run
    std::vector<Grain> g = src.kind == ParticleSource::Kind::csv       ? read_csv_grains(src)
                           : src.kind == ParticleSource::Kind::lattice ? lattice_grains(src)
                                                                       : random_grains(src, sc.domain, rng);
    for (auto& grain : g) {
      if (!sc.domain.inside(grain.position))
        fail_at(grain.where, "particle centre " + format_vec(grain.position) + " is outside the domain " +
                                 format_vec(sc.domain.lower) + " - " + format_vec(sc.domain.upper));
      grain.position = sc.domain.wrap(grain.position);
      const auto& mat = sc.materials[static_cast<std::size_t>(src.material)];
      w.particles.add(static_cast<std::int64_t>(grains.size()), src.material, grain.diameter, mat.density,
                      grain.position, grain.velocity);
      grains.push_back(grain);
      // Generated grains may touch (a lattice at spacing = diameter); allow for round-off.
      tolerance.push_back(src.kind == ParticleSource::Kind::csv ? src.overlap_tolerance : 1e-9);
    }
  }
  double d_max = 2 * std::accumulate(w.particles.radius.begin(), w.particles.radius.end(), 0.0,
                                     [](double a, double b) { return std::max(a, b); });
  for (const auto& src : sc.sources)
    if (src.kind == ParticleSource::Kind::inflow) d_max = std::max(d_max, src.sizes.largest());
  for (int k = 0; k < 3; ++k)
    if (sc.domain.periodic[k] && sc.domain.length(k) < 2 * d_max) {
      std::ostringstream s;
      s << "the periodic length along " << "xyz"[k] << " (" << sc.domain.length(k)
        << " m) must be at least twice the largest diameter (" << d_max << " m)";
      fail_at(sc.domain_where, s.str());
    }
  check_overlaps(w, grains, tolerance);
  return w;
}

}  // namespace tsubu
