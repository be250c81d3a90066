#include "tsubu/source/build_world.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/core/format.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/search/triangle_grid.hpp"
#include "tsubu/source/size_moments.hpp"
#include "tsubu/source/sources.hpp"

namespace tsubu {

namespace {

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

// Overlapping input particles beyond each source's tolerance are an input error naming the
// first grain, in input order, that overlaps an earlier one, and the earliest it overlaps.
// The grid keeps memory O(N), and the check stops at the first offence: no list of all
// pairs, which a unit slip (diameters in mm) makes N^2 long.
void check_overlaps(const World& w, const std::vector<Grain>& grains, const std::vector<double>& tolerance) {
  const Particles& p = w.particles;
  if (p.size() == 0) return;  // an inflow alone starts empty
  CellGrid grid;
  grid.bin(p, w.domain, 2 * *std::max_element(p.radius.begin(), p.radius.end()));
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::size_t earliest = i;
    double ratio = 0;
    grid.for_each_near(i, w.domain, [&](std::uint32_t j) {
      if (j >= earliest) return;
      const double overlap = p.radius[i] + p.radius[j] - norm(w.domain.separation(p.position[i], p.position[j]));
      const double r = overlap / (2 * std::min(p.radius[i], p.radius[j]));
      if (r > std::min(tolerance[i], tolerance[j])) earliest = j, ratio = r;
    });
    if (earliest == i) continue;
    const Grain& b = grains[earliest];
    std::ostringstream s;
    s << "particle overlaps the one from " << b.where.file << ":" << b.where.line << " by " << ratio
      << " of the smaller diameter; allowed up to " << std::min(tolerance[i], tolerance[earliest])
      << " (overlap_tolerance of csv and file sources; lattice and random particles may only touch)";
    throw InputError(grains[i].where, s.str());
  }
}

// A particle that starts deeper in a wall than simulation.overlap_limit would stop the run
// at its first force evaluation; `check` reports it here, as the run sees it (a wall pushes
// only centres in front of its surface). So is one on the far side of a cylinder or of a
// cone's face, which would never feel it (a plane may leave particles behind it: another part
// of the box; so may a cone beyond its rims). A mesh is two-sided: its depth is from the
// nearest of its triangles, found through a grid of them (cells a largest grain wide).
void check_walls(const World& w, double overlap_limit, const std::vector<Grain>& grains) {
  const Particles& p = w.particles;
  if (p.size() == 0) return;
  const double widest = 2 * *std::max_element(p.radius.begin(), p.radius.end());
  std::vector<std::optional<TriangleGrid>> grids(w.walls.size());
  for (std::size_t k = 0; k < w.walls.size(); ++k)
    if (const TriangleMesh* mesh = w.walls[k].mesh.get()) grids[k].emplace(*mesh, TriangleGrid::cell_for(*mesh, widest));
  std::vector<std::uint32_t> near;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t k = 0; k < w.walls.size(); ++k) {
      const Wall& wall = w.walls[k];
      std::string which = std::to_string(k);
      double dist = 0;
      if (wall.mesh) {
        const auto nearest = grids[k]->nearest_within(*wall.mesh, wall.to_mesh(p.position[i]), p.radius[i], near);
        if (!nearest) continue;
        dist = nearest->distance;
        which += ", a mesh (triangle " + std::to_string(nearest->triangle) + "),";
      } else {
        dist = wall.touch(p.position[i]).distance;
        if (const WallShape shape = wall.shape; shape != WallShape::plane && !(dist > 0))
          throw InputError(grains[i].where, "particle centre " + format_vec(p.position[i]) + " starts " +
                                                (wall.inside ? "outside" : "inside") + " wall " + which +
                                                (shape == WallShape::cone ? ", a cone" : ", a cylinder") + " with the particles " +
                                                (wall.inside ? "inside" : "outside") + " it: place the particles on its side");
        if (!(dist > 0)) continue;
      }
      const double ratio = (p.radius[i] - dist) / (2 * p.radius[i]);
      if (!(ratio <= overlap_limit)) {
        std::ostringstream s;
        s << "particle centre " << format_vec(p.position[i]) << " (diameter " << 2 * p.radius[i] << " m) starts inside wall "
          << which << " by " << ratio << " of its diameter; allowed up to simulation.overlap_limit = " << overlap_limit
          << " (move the particle or the wall)";
        throw InputError(grains[i].where, s.str());
      }
    }
}

// output.track names particles by id: ids run 0..N-1 in the order of [[particles]].
void check_tracked(const Scenario& sc, const World& w) {
  const auto n = static_cast<std::int64_t>(w.particles.size());
  // With an inflow, ids from n on belong to grains still to come: their rows start when
  // they enter.
  const bool inflow = inflow_source(sc) != nullptr;
  for (std::int64_t id : sc.output.track)
    if (id < 0 || (id >= n && !inflow))
      throw InputError(sc.output.where, "no particle has id " + std::to_string(id) + "; ids run from 0 to " + std::to_string(n - 1) +
                           " in the order of [[particles]]");
}

// The inflow builds its column a slab at a time, before the slab's first grain enters:
// counted first, as the random source counts its grains, so that a very wide mixture is
// refused instead of drawing grains for hours.
void check_inflow_slab(const Scenario& sc, const ParticleSource& src) {
  const InflowColumn c = inflow_column(sc, src);
  const double grains = c.slab_grains();
  if (grains <= static_cast<double>(particle_limit())) return;
  std::ostringstream s;
  s << "a slab of the inflow's column (" << format_number(c.slab_height()) << " m high over the domain's base, solid_fraction "
    << format_number(c.solid_fraction) << ") would hold " << std::setprecision(3) << grains
    << " grains of this distribution (a mean grain volume of " << mean_grain_volume(c.sizes)
    << " m^3); this machine holds at most " << particle_limit()
    << " particles: narrow the distribution (a larger smallest diameter) or lower solid_fraction";
  throw InputError(src.at("distribution"), s.str());
}

// An insertion releases at most its mass rate over the run after its start, and at most its
// mass_limit: counted from the distribution's mean grain, as the inflow's slab is, so that a
// rate typed in the wrong unit is refused instead of filling the memory.
void check_insertion_count(const Scenario& sc, const ParticleSource& src) {
  const Insertion i = insertion_of(sc, src);
  const double rate_mass = i.mass_rate > 0 ? i.mass_rate * std::max(0.0, sc.duration - i.start) : INFINITY;
  const double mass = i.mass_limit > 0 ? std::min(i.mass_limit, rate_mass) : rate_mass;
  const double grains = mass / (i.density * mean_grain_volume(i.sizes));
  if (grains <= static_cast<double>(particle_limit())) return;
  std::ostringstream s;
  s << "the insertion would release " << std::setprecision(3) << grains << " grains of this distribution in the run ("
    << format_number(mass) << " kg, a mean grain of " << i.density * mean_grain_volume(i.sizes)
    << " kg); this machine holds at most " << particle_limit()
    << " particles: lower mass_rate (kg/s) or mass_limit (kg), or shorten the run";
  throw InputError(src.at(i.mass_limit > 0 && i.mass_limit <= rate_mass ? "mass_limit" : "mass_rate"), s.str());
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

Insertion insertion_of(const Scenario& sc, const ParticleSource& src) {
  Insertion i;
  i.region = src.region;
  i.sizes = src.sizes;
  i.density = sc.materials[static_cast<std::size_t>(src.material)].density;
  i.mass_rate = src.mass_rate;
  i.mass_limit = src.mass_limit;
  i.start = src.start;
  i.velocity = src.velocity;
  return i;
}

World build_empty_world(const Scenario& sc) {
  World w;
  w.domain = sc.domain;
  w.walls = sc.walls;
  w.index_wall_elements();
  for (Wall& wall : w.walls) wall.surface_during(0.5 * sc.dt);  // as the first step's evaluation sees it
  w.dt = sc.dt;
  return w;
}

Model build_model(const Scenario& sc) {
  Model m;
  m.materials = sc.materials;
  m.laws = build_laws(sc);
  m.gravity = sc.gravity;
  m.fluid = sc.fluid;
  m.search = sc.search;
  m.overlap_limit = sc.overlap_limit;
  m.skin = sc.skin;
  return m;
}

World build_world(const Scenario& sc) {
  World w = build_empty_world(sc);
  Random rng(sc.seed);
  std::vector<Grain> grains;
  std::vector<double> tolerance;
  for (const auto& src : sc.sources) {
    const auto first = static_cast<std::int64_t>(grains.size());
    w.source_ids.emplace_back(first, first);
    if (src.kind == ParticleSource::Kind::inflow) {  // its grains arrive during the run
      check_inflow_slab(sc, src);
      continue;
    }
    if (src.kind == ParticleSource::Kind::insertion) {  // so do these
      check_insertion_count(sc, src);
      continue;
    }
    std::vector<Grain> g = src.kind == ParticleSource::Kind::csv       ? read_csv_grains(src)
                           : src.kind == ParticleSource::Kind::file    ? read_state_grains(src, sc.materials.size())
                           : src.kind == ParticleSource::Kind::lattice ? lattice_grains(src)
                                                                       : random_grains(src, sc.domain, rng);
    const bool from_file = src.kind == ParticleSource::Kind::csv || src.kind == ParticleSource::Kind::file;
    for (auto& grain : g) {
      if (!sc.domain.inside(grain.position))
        throw InputError(grain.where, "particle centre " + format_vec(grain.position) + " is outside the domain " +
                                 format_vec(sc.domain.lower) + " - " + format_vec(sc.domain.upper));
      grain.position = sc.domain.wrap(grain.position);
      const int material = grain.material >= 0 ? grain.material : src.material;
      const auto& mat = sc.materials[static_cast<std::size_t>(material)];
      w.particles.add(static_cast<std::int64_t>(grains.size()), material, grain.diameter, mat.density,
                      grain.position, grain.velocity);
      w.particles.omega.back() = grain.omega;
      // A diameter too small (or large) for doubles gives a zero, subnormal or infinite mass
      // or inertia, which the integrators divide by.
      const double mass = w.particles.mass.back(), inertia = w.particles.inertia.back();
      if (!std::isnormal(mass) || !std::isnormal(inertia)) {
        std::ostringstream s;
        s << "the diameter " << grain.diameter << " m gives a mass of " << mass << " kg and a moment of inertia of "
          << inertia << " kg m^2 (density " << mat.density
          << " kg/m^3); diameters are in metres and must give a finite, non-zero mass and inertia";
        throw InputError(grain.where, s.str());
      }
      // Every energy of series.csv sums these: each must be a finite double.
      const std::size_t i = w.particles.size() - 1;
      if (!std::isfinite(w.particles.translational_energy(i)) || !std::isfinite(w.particles.rotational_energy(i))) {
        std::ostringstream s;
        s << "the velocity " << format_vec(grain.velocity) << " m/s and spin " << format_vec(grain.omega)
          << " rad/s give a kinetic energy of " << w.particles.translational_energy(i) << " J and a rotational energy of "
          << w.particles.rotational_energy(i) << " J (diameter " << grain.diameter
          << " m); they must give finite energies (velocities in m/s, spins in rad/s)";
        throw InputError(grain.where, s.str());
      }
      grains.push_back(grain);
      // Generated grains may touch (a lattice at spacing = diameter); allow for round-off.
      tolerance.push_back(from_file ? src.overlap_tolerance : 1e-9);
    }
    w.source_ids.back().second = static_cast<std::int64_t>(grains.size());
  }
  if (const ParticleSource* arriving = inflow_source(sc))  // the inflow's or insertion's ids follow the built grains
    w.source_ids[static_cast<std::size_t>(arriving - sc.sources.data())] = {static_cast<std::int64_t>(grains.size()),
                                                                              std::numeric_limits<std::int64_t>::max()};
  double d_max = 2 * std::accumulate(w.particles.radius.begin(), w.particles.radius.end(), 0.0,
                                     [](double a, double b) { return std::max(a, b); });
  if (const ParticleSource* arriving = inflow_source(sc)) d_max = std::max(d_max, arriving->sizes.largest());
  for (int k = 0; k < 3; ++k)
    if (sc.domain.periodic[k] && sc.domain.length(k) < 2 * d_max) {
      std::ostringstream s;
      s << "the periodic length along " << "xyz"[k] << " (" << sc.domain.length(k)
        << " m) must be at least twice the largest diameter (" << d_max << " m)";
      throw InputError(sc.domain_where, s.str());
    }
  // Hindered settling sums each grain's neighbours once, at their nearest image: a ball of c
  // radii around the largest grain, with a largest grain at its edge, must fit in half the
  // periodic length.
  const double c = sc.fluid.hindered_ball_ratio;
  for (int k = 0; k < 3; ++k)
    if (sc.fluid.enabled && sc.fluid.hindered && sc.domain.periodic[k] && sc.domain.length(k) < (c + 1) * d_max) {
      std::ostringstream s;
      s << "a ball of " << c << " radii around the largest grain (" << d_max << " m) and a grain at its edge need a periodic length of at least (ratio + 1) d_max = "
        << (c + 1) * d_max << " m, but the length along " << "xyz"[k] << " is " << sc.domain.length(k)
        << " m; allowed: a ratio up to " << sc.domain.length(k) / d_max - 1;
      throw InputError(sc.fluid_where, s.str());
    }
  check_overlaps(w, grains, tolerance);
  check_walls(w, sc.overlap_limit, grains);
  check_tracked(sc, w);
  return w;
}

}  // namespace tsubu
