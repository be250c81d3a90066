#include "tsubu/sim/time_scales.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/integrate/block_hermite.hpp"
#include "tsubu/sim/simulation.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

double sphere_mass(double rho, double d) { return rho * M_PI * d * d * d / 6; }

// The smallest and the largest grain of each material: those present and, for an inflow
// source, the bounds of its size distribution.
std::vector<GrainTimes> grain_sizes(const Scenario& sc, const World& w) {
  std::vector<GrainTimes> g;
  auto add = [&](int material, double d) {
    for (GrainTimes& x : g)
      if (x.material == material && x.diameter == d) return;
    GrainTimes x;
    x.material = material;
    x.diameter = d;
    g.push_back(x);
  };
  for (std::size_t m = 0; m < sc.materials.size(); ++m) {
    double lo = INFINITY, hi = 0;
    for (std::size_t i = 0; i < w.particles.size(); ++i)
      if (w.particles.material[i] == static_cast<int>(m)) lo = std::min(lo, 2 * w.particles.radius[i]), hi = std::max(hi, 2 * w.particles.radius[i]);
    if (hi > 0) add(static_cast<int>(m), lo), add(static_cast<int>(m), hi);
  }
  if (const ParticleSource* src = inflow_source(sc)) {
    add(src->material, src->sizes.smallest());
    add(src->material, src->sizes.largest());
  }
  std::sort(g.begin(), g.end(), [](const GrainTimes& a, const GrainTimes& b) {
    return a.material != b.material ? a.material < b.material : a.diameter < b.diameter;
  });
  return g;
}

// The representative approach speed of a collision: the largest of the free-fall speed over
// the domain's height, the terminal speed of the largest grain in a fluid, twice the largest
// initial speed (two grains head on), the inflow's entry speed, the fastest wall and the
// fastest point of a wall's moving surface in the box.
void impact_speed(const Scenario& sc, const World& w, TimeScales& ts) {
  auto consider = [&](double u, const std::string& why) {
    if (u > ts.impact_speed) ts.impact_speed = u, ts.impact_reason = why;
  };
  const double g = norm(sc.gravity);
  if (g > 0) {
    double height = 0;  // the box's extent along gravity
    for (int k = 0; k < 3; ++k) height += std::abs(sc.gravity[k]) / g * sc.domain.length(k);
    consider(std::sqrt(2 * g * height), "free fall over the domain height, " + fmt(height) + " m");
  }
  for (const GrainTimes& x : ts.grains)
    consider(x.terminal_speed, "terminal settling speed of the " + fmt(x.diameter) + " m " + sc.materials[x.material].name + " grain");
  double fastest = 0;
  for (const Vec3& v : w.particles.velocity) fastest = std::max(fastest, norm(v));
  consider(2 * fastest, "twice the largest initial particle speed");
  if (const ParticleSource* src = inflow_source(sc))
    consider(src->kind == ParticleSource::Kind::insertion ? norm(src->velocity) : src->fall_speed,
             src->kind == ParticleSource::Kind::insertion ? "the insertion's speed" : "the inflow's entry speed");
  for (const Wall& wall : sc.walls)
    for (const WallMotion& m : wall.motion) consider(norm(m.velocity) + fastest, "a moving wall");
  for (const Wall& wall : sc.walls) {  // a moving surface: its fastest point in the box (a corner, for a turntable)
    if (!wall.surface_moves()) continue;
    std::vector<Wall> stretches(1, wall);  // each stretch of its surface's motion, or its constant motion
    for (const SurfaceMotion& m : wall.surface_motion) {
      stretches.push_back(wall);
      stretches.back().surface_during(0.5 * m.until + 0.5 * (&m == wall.surface_motion.data() ? 0.0 : (&m - 1)->until));
    }
    double surface = 0;
    for (const Wall& stretch : stretches)
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 x{(corner & 1 ? sc.domain.upper : sc.domain.lower).x, (corner & 2 ? sc.domain.upper : sc.domain.lower).y,
                     (corner & 4 ? sc.domain.upper : sc.domain.lower).z};
        surface = std::max(surface, norm(stretch.surface_velocity_at(x) - stretch.velocity));
      }
    consider(surface + fastest, "a wall's moving surface");
  }
  consider(sc.block_steps.u_floor, "no motion foreseen: the floor " + fmt(sc.block_steps.u_floor) + " m/s");
}

// The shortest collision over every pair of the grains and every wall (a material with a
// single grain and no inflow has no pairs of its own), and the deepest overlap of one at the
// impact speed.
void shortest_contact(const Scenario& sc, const World& w, const LawTable& laws, TimeScales& ts) {
  ts.shortest_contact = INFINITY;
  std::vector<bool> several(sc.materials.size(), false);
  std::vector<std::size_t> count(sc.materials.size(), 0);
  for (int m : w.particles.material) several[static_cast<std::size_t>(m)] = ++count[static_cast<std::size_t>(m)] > 1;
  if (const ParticleSource* src = inflow_source(sc)) several[static_cast<std::size_t>(src->material)] = true;
  auto consider = [&](const PairLaw& law, double m_eff, double r_eff, double d_small, const std::string& what) {
    const double t = contact_time(law.normal, m_eff, r_eff, ts.impact_speed);
    if (t < ts.shortest_contact) {
      ts.shortest_contact = t;
      ts.shortest_contact_what = what + ", " + std::string(label_of(law.normal));
      ts.contact_resolution_matters = !exact_whatever_dt(law.normal);
    }
    const double overlap = peak_overlap(law.normal, m_eff, r_eff, ts.impact_speed) / d_small;
    if (overlap > ts.deepest_overlap) ts.deepest_overlap = overlap, ts.deepest_overlap_what = what + ", " + std::string(label_of(law.normal));
  };
  auto name = [&](const GrainTimes& x) { return fmt(x.diameter) + " m " + sc.materials[x.material].name; };
  for (std::size_t a = 0; a < ts.grains.size(); ++a) {
    const GrainTimes& ga = ts.grains[a];
    const double ma = sphere_mass(sc.materials[ga.material].density, ga.diameter), ra = ga.diameter / 2;
    for (std::size_t b = a; b < ts.grains.size(); ++b) {
      const GrainTimes& gb = ts.grains[b];
      if (ga.material == gb.material && !several[static_cast<std::size_t>(ga.material)]) continue;  // one grain alone
      const double mb = sphere_mass(sc.materials[gb.material].density, gb.diameter), rb = gb.diameter / 2;
      consider(laws.at(ga.material, gb.material), ma * mb / (ma + mb), ra * rb / (ra + rb), 2 * std::min(ra, rb),
               name(ga) + " on " + name(gb));
    }
    for (const Wall& wall : w.walls)
      consider(laws.at(ga.material, wall.material), ma, ra, ga.diameter,
               name(ga) + " on a " + sc.materials[wall.material].name + " wall");
  }
}

// What the rules ask of dt, whether the scenario's dt meets it, and the warnings.
void judge_dt(const Scenario& sc, TimeScales& ts) {
  const double dt = sc.dt;
  const bool contacts = std::isfinite(ts.shortest_contact) && ts.contact_resolution_matters;
  const bool fluid = std::isfinite(ts.shortest_relaxation);
  if (sc.integrator == Integrator::block_hermite) {
    // dt is the longest step; a contact's step is kappa_c t_c, a grain's in the fluid
    // eta_tau tau; each must be reachable by halving dt at most `levels` times.
    const BlockStepRules& r = sc.block_steps;
    double finest = INFINITY;
    std::string what;
    if (contacts) finest = r.kappa_c * ts.shortest_contact, what = "kappa_c t_c = " + fmt(r.kappa_c) + " x " + fmt(ts.shortest_contact) + " s";
    if (fluid && r.eta_tau * ts.shortest_relaxation < finest)
      finest = r.eta_tau * ts.shortest_relaxation, what = "eta_tau tau = " + fmt(r.eta_tau) + " x " + fmt(ts.shortest_relaxation) + " s";
    ts.needed_level = std::isfinite(finest) ? level_needed(dt, finest) : 0;
    ts.suggested_dt = std::isfinite(finest) ? std::ldexp(finest, r.levels) : dt;
    ts.safe = ts.needed_level <= r.levels;
    // A step rule's value so small that the step underflows needs no level a run can have.
    const std::string level = ts.needed_level < kBeyondLevels ? "level " + std::to_string(ts.needed_level)
                                                              : "a finer level than any (a step rule's value is too small)";
    if (!std::isfinite(finest))
      ts.suggestion = "no contact or fluid bounds the steps";
    else if (ts.needed_level < kBeyondLevels)
      ts.suggestion = "the finest step needed is " + what + " = " + fmt(finest) + " s: " + level + " of " +
                      std::to_string(r.levels) + " (dt/2^" + std::to_string(ts.needed_level) + " = " +
                      fmt(std::ldexp(dt, -ts.needed_level)) + " s); dt may be up to 2^" + std::to_string(r.levels) +
                      " times that";
    else
      ts.suggestion = "the finest step needed is " + what + " = " + fmt(finest) + " s: " + level;
    if (ts.needed_level >= kBeyondLevels)
      ts.warnings.push_back("no dt can resolve the stiffest contact or the drag: " + what + " = " + fmt(finest) +
                            " s needs " + level + "; raise the value in simulation.block_steps");
    else if (!ts.safe)
      ts.warnings.push_back("dt = " + fmt(dt) + " s cannot resolve the stiffest contact or the drag: " + what + " = " +
                            fmt(finest) + " s needs " + level + ", beyond levels = " +
                            std::to_string(r.levels) + " (finest step dt/2^" + std::to_string(r.levels) + " = " +
                            fmt(std::ldexp(dt, -r.levels)) + " s); lower dt to " + fmt(ts.suggested_dt) +
                            " s or raise simulation.block_steps.levels");
    return;
  }
  ts.suggested_dt = INFINITY;
  if (contacts) {
    ts.suggested_dt = ts.shortest_contact / kStepsPerContact;
    ts.suggestion = "1/" + fmt(kStepsPerContact) + " of the shortest contact";
  }
  if (fluid && kRelaxationShare * ts.shortest_relaxation < ts.suggested_dt) {
    ts.suggested_dt = kRelaxationShare * ts.shortest_relaxation;
    ts.suggestion = fmt(kRelaxationShare) + " of the shortest drag relaxation time";
  }
  if (!std::isfinite(ts.suggested_dt)) ts.suggested_dt = dt, ts.suggestion = "no contact or fluid bounds dt";
  ts.safe = dt <= ts.suggested_dt * (1 + 1e-12);
  if (contacts && dt * kFewestContactSteps > ts.shortest_contact)
    ts.warnings.push_back("dt = " + fmt(dt) + " s cannot resolve the stiffest contact: it lasts " +
                          fmt(ts.shortest_contact) + " s (" + ts.shortest_contact_what + ", at " + fmt(ts.impact_speed) +
                          " m/s), only " + fmt(ts.shortest_contact / dt) + " steps; at least " + fmt(kFewestContactSteps) +
                          " are needed, " + fmt(kStepsPerContact) + " suggested: dt <= " + fmt(ts.suggested_dt) + " s");
  if (fluid && dt > kLargestRelaxationShare * ts.shortest_relaxation)
    ts.warnings.push_back("dt = " + fmt(dt) + " s cannot resolve the drag: its relaxation time is " +
                          fmt(ts.shortest_relaxation) + " s; keep dt <= " + fmt(kLargestRelaxationShare) +
                          " of it, " + fmt(kRelaxationShare) + " suggested: dt <= " + fmt(ts.suggested_dt) + " s");
}

// Below this many touching contacts a grain, grains under gravity start apart: they will
// fall and pack (a packed bed has about 3 a grain, pairs and walls counted once).
constexpr double kLooseContacts = 1;

// Why a sample of the start cannot tell the run's cost (empty when it can).
std::string why_no_estimate(const Scenario& sc, std::size_t grains, double contacts_per_grain) {
  if (inflow_source(sc))
    return "the inflow brings its grains during the run, and the cost of a step grows with them (the sample holds the " +
           std::to_string(grains) + " present at the start)";
  if (grains > 0 && norm(sc.gravity) > 0 && contacts_per_grain < kLooseContacts)
    return "the grains start apart (" + fmt(contacts_per_grain) +
           " contacts a grain) and will fall and pack; a packed bed, and the neighbour lists rebuilt while the grains "
           "fall, cost several times more a step than the start (5 to 60 times in the settling beds measured)";
  return "";
}

}  // namespace

double rayleigh_time(const Material& m, double d) {
  const double shear = m.youngs_modulus / (2 * (1 + m.poisson));
  return M_PI * (d / 2) * std::sqrt(m.density / shear) / (0.1631 * m.poisson + 0.8766);
}

TimeScales time_scales(const Scenario& sc, const World& w) {
  TimeScales ts;
  ts.grains = grain_sizes(sc, w);
  const bool drag = sc.fluid.enabled && sc.fluid.drag;
  ts.shortest_relaxation = INFINITY;
  for (GrainTimes& x : ts.grains) {
    const Material& m = sc.materials[x.material];
    x.rayleigh_time = rayleigh_time(m, x.diameter);
    x.relaxation_time = INFINITY;
    if (!drag) continue;
    x.terminal_speed = terminal_speed(sc.fluid, m.density, x.diameter, norm(sc.gravity));
    x.relaxation_time = drag_relaxation_time(sc.fluid, x.diameter, sphere_mass(m.density, x.diameter) + sc.fluid.added_mass_of(x.diameter),
                                             x.terminal_speed);
    ts.shortest_relaxation = std::min(ts.shortest_relaxation, x.relaxation_time);
  }
  impact_speed(sc, w, ts);
  // Each grain's collision with an equal one, at the impact speed.
  const LawTable laws = build_model(sc).laws;
  for (GrainTimes& x : ts.grains) {
    const double m = sphere_mass(sc.materials[x.material].density, x.diameter);
    x.contact_time = contact_time(laws.at(x.material, x.material).normal, m / 2, x.diameter / 4, ts.impact_speed);
  }
  shortest_contact(sc, w, laws, ts);
  ts.steps = std::llround(sc.duration / sc.dt);
  judge_dt(sc, ts);
  // Whatever dt is, grains too soft for their impact speed press deeper than the limit.
  if (ts.deepest_overlap > sc.overlap_limit)
    ts.warnings.push_back("a collision at the impact speed, " + fmt(ts.impact_speed) + " m/s (" + ts.impact_reason + "), presses " +
                          ts.deepest_overlap_what + " to an overlap of " + fmt(ts.deepest_overlap) +
                          " of the smaller diameter (elastic estimate; damping makes it shallower), beyond "
                          "simulation.overlap_limit = " + fmt(sc.overlap_limit) + ": the run would stop whatever dt is; "
                          "the grains are too soft for this speed: a stiffer material (youngs_modulus) or a larger "
                          "simulation.overlap_limit");
  return ts;
}

WallTimeEstimate estimate_wall_time(const Scenario& sc, World world, std::int64_t max_steps, double budget_s) {
  using clock = std::chrono::steady_clock;
  WallTimeEstimate e;
  Simulation sim(std::move(world), build_model(sc), sc.integrator, sc.block_steps);
  try {
    sim.start();
    const auto t0 = clock::now();
    const std::int64_t last = std::min<std::int64_t>(max_steps, std::llround(sc.duration / sc.dt));
    while (e.sampled_steps < last && e.sample_seconds < budget_s) {
      sim.step();
      ++e.sampled_steps;
      e.sample_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    }
  } catch (const NumericalError& err) {
    e.failure = err.what();
  }
  if (e.sampled_steps > 0)
    e.run_seconds = e.sample_seconds / static_cast<double>(e.sampled_steps) * static_cast<double>(std::llround(sc.duration / sc.dt));
  e.particles = sim.world().particles.size();
  if (e.particles > 0 && e.failure.empty())
    e.contacts_per_grain = static_cast<double>(sim.forces().totals(sim.world()).contacts) / static_cast<double>(e.particles);
  e.cannot = why_no_estimate(sc, e.particles, e.contacts_per_grain);
  return e;
}

}  // namespace tsubu
