#include "tsubu/forces/force_field.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/core/exact_sum.hpp"
#include "tsubu/core/parallel.hpp"
#include "tsubu/forces/evaluate.hpp"
#include "tsubu/forces/gather.hpp"

namespace tsubu {

void ForceField::Results::resize(std::size_t n, bool shifts, bool rolls) {
  entry.resize(n);
  shift_i.resize(shifts ? n : 0);  // cleared by the evaluations, entry by entry
  shift_j.resize(shifts ? n : 0);
  rolling_i.resize(rolls ? n : 0);
}

void ForceField::Results::follow(const std::vector<std::uint32_t>& origin) {
  ContactList::follow(entry, origin);
  ContactList::follow(shift_i, origin);
  ContactList::follow(shift_j, origin);
  ContactList::follow(rolling_i, origin);
}

void ForceField::follow_lists(const ContactList& contacts) {
  pair_results_.follow(contacts.pair_origin());
  wall_results_.follow(contacts.wall_origin());
  ContactList::follow(pair_rates_, contacts.pair_origin());
  ContactList::follow(wall_rates_, contacts.wall_origin());
}

void ForceField::renumbered(const World& world) {
  if (keeps_records_) follow_lists(world.contacts);  // fixed steps' records are remade at the rebuild
  built_at_.clear();
  admitted_ = std::min(admitted_, world.particles.size());  // some may have been removed
}

namespace {

// m + C_M rho_f V (Particles::translational_mass).
double translational_mass_of(const Particles& p, std::size_t i, const Fluid& fluid) {
  return p.mass[i] + fluid.added_mass_of(2 * p.radius[i]);
}

}  // namespace

void ForceField::admit_new_particles(Particles& p) {
  for (std::size_t i = admitted_; i < p.size(); ++i) p.translational_mass[i] = translational_mass_of(p, i, model_->fluid);
  admitted_ = p.size();
}

namespace {

// Particles per call to body_loads (the gather's, welcome's), whose fluid loads are taken together.
constexpr std::size_t kBodyBatch = 64;

}  // namespace

void ForceField::welcome(Particles& p, std::size_t first) const {
  for (std::size_t i = first; i < p.size(); ++i) p.translational_mass[i] = translational_mass_of(p, i, model_->fluid);
  BodyLoad bodies[kBodyBatch];
  for (std::size_t i = first; i < p.size(); ++i) {
    if ((i - first) % kBodyBatch == 0) body_loads(p, i, std::min(p.size(), i + kBodyBatch), 0, true, bodies);
    p.force[i] = bodies[(i - first) % kBodyBatch].force;
    p.torque[i] = bodies[(i - first) % kBodyBatch].torque;
    p.contact_count[i] = 0;
  }
}

void ForceField::body_loads(const Particles& p, std::size_t first, std::size_t last, double fluid_lead, bool lone,
                            BodyLoad* out) const {
  for (std::size_t i = first; i < last; ++i) out[i - first] = {p.mass[i] * model_->gravity, {}};
  if (!model_->fluid.enabled) return;
  double d[kBodyBatch];
  Vec3 u[kBodyBatch], w[kBodyBatch];
  Crowding crowd[kBodyBatch];
  FluidLoad fluid[kBodyBatch];
  for (std::size_t begin = first; begin < last; begin += kBodyBatch) {
    const std::size_t n = std::min(kBodyBatch, last - begin);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = begin + k;
      d[k] = 2 * p.radius[i];
      u[k] = p.velocity[i], w[k] = p.omega[i];
      if (fluid_lead != 0)
        u[k] += (fluid_lead / p.translational_mass[i]) * p.force[i], w[k] += (fluid_lead / p.inertia[i]) * p.torque[i];
      crowd[k] = lone ? kLone : crowding(i);
    }
    fluid_loads(model_->fluid, model_->gravity, n, d, u, w, crowd, fluid);
    for (std::size_t k = 0; k < n; ++k) {
      BodyLoad& body = out[begin + k - first];
      body.force += fluid[k].force;
      body.torque = fluid[k].torque;
    }
  }
}

void ForceField::compute(World& world, double fluid_lead) {
  if (neighbourhood_ && neighbourhood_->update(world, false)) built_at_.clear();
  admit_new_particles(world.particles);
  if (needs_rebuild(world)) rebuild(world);
  evaluate_pairs(world);
  evaluate_walls(world);
  if (!crowd_list_.empty()) {
    const Particles& p = world.particles;
    parallel_for(p.size(), [&](std::size_t i) {
      crowding_[i] = crowd_list_.of<false>(world, i, [&](std::size_t j) { return PointMotion{p.position[j], p.velocity[j]}; });
    });
  }
  accumulate(world, fluid_lead);
  started_ = true;
}

bool ForceField::needs_rebuild(const World& world) const {
  const Particles& p = world.particles;
  if (built_at_.size() != p.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  const int threads = threads_for(p.size());
  std::vector<char> moved(static_cast<std::size_t>(threads), 0);
  for_each_thread(threads, [&](int t) {
    const auto [begin, end] = static_range(p.size(), t, threads);
    for (std::size_t i = begin; i < end && !moved[static_cast<std::size_t>(t)]; ++i)
      moved[static_cast<std::size_t>(t)] = norm2(world.domain.separation(p.position[i], built_at_[i])) > limit2;
  });
  if (std::find(moved.begin(), moved.end(), 1) != moved.end()) return true;
  return walls_moved(world);
}

bool ForceField::walls_moved(const World& world) const {
  if (walls_built_at_.size() != world.walls.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  for (std::size_t w = 0; w < world.walls.size(); ++w) {
    const Wall& wall = world.walls[w];
    double shift = norm(wall.point - walls_built_at_[w]);  // moving walls
    if (wall.mesh && !(wall.turn_axis == Vec3{})) {  // a turning mesh: its farthest point's arc since
      const auto [c, s] = walls_turn_at_[w];
      shift += mesh_reach_[w] * std::abs(std::atan2(wall.turn_sin * c - wall.turn_cos * s, wall.turn_cos * c + wall.turn_sin * s));
    }
    if (shift * shift > limit2) return true;
  }
  return false;
}

void ForceField::record_walls(const World& world) {
  walls_built_at_.clear();
  walls_turn_at_.clear();
  for (const Wall& w : world.walls) walls_built_at_.push_back(w.point), walls_turn_at_.emplace_back(w.turn_cos, w.turn_sin);
}

double ForceField::skin_of(const World& world) const {
  const Particles& p = world.particles;
  return p.size() == 0 ? model_->skin : skin_for(*std::min_element(p.radius.begin(), p.radius.end()));
}

double ForceField::reach_per_radius() const {
  return model_->fluid.enabled && model_->fluid.hindered ? model_->fluid.hindered_ball_ratio + 1 : 2.0;
}

void ForceField::rebuild(World& world) {
  const Particles& p = world.particles;
  skin_ = skin_of(world);
  build_lists(world, p, skin_, {}, false);
  built_at_ = p.position;
  record_walls(world);
}

void ForceField::rebuild_at(World& world, const std::vector<Vec3>& positions, const std::vector<double>& reach,
                            const std::vector<double>& wall_reach) {
  const Particles& p = world.particles;
  skin_ = skin_of(world);
  Particles probe;
  probe.position = positions;
  probe.radius.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) probe.radius[i] = p.radius[i] + reach[i];
  build_lists(world, probe, skin_, wall_reach, true);
  built_at_.clear();  // compute() would rebuild: block steps decide when lists are stale
  record_walls(world);
}

void ForceField::build_lists(World& world, const Particles& probe, double margin, const std::vector<double>& wall_reach,
                             bool keep_records) {
  // Peak memory: the contact index is remade after a build, and so are the per-contact
  // records unless kept, so they are freed before it, and the old lists and the search's
  // candidates after it.
  keeps_records_ = keep_records;
  if (!keep_records) pair_results_ = {}, wall_results_ = {}, pair_rates_ = {}, wall_rates_ = {};
  ContactList& contacts = world.contacts;
  contacts.release_index();
  grid_.configure(model_->search);
  std::vector<Pair> candidates;
  // A run split among processes lists only the contacts of its own particles: a pair of two
  // copies of other processes' particles (World::ghosts), or a copy and a wall, is evaluated
  // by the process that owns them.
  const std::size_t owned = world.owned();
  grid_.find_pairs(probe, world.domain, margin, candidates);
  std::erase_if(candidates, [&](const Pair& e) { return e.i >= owned && e.j >= owned; });
  contacts.carry_pairs(candidates, world.particles);
  find_wall_contacts(world, probe, margin, wall_reach, candidates);
  std::erase_if(candidates, [&](const Pair& e) { return e.i >= owned; });
  contacts.carry_walls(candidates);
  contacts.index(world.particles);
  if (keep_records) follow_lists(contacts);
  build_crowd_list(world, probe, margin, candidates);
  pair_law_ = nullptr;  // the law every listed pair shares: grains all of one material
  const std::vector<int>& material = world.particles.material;
  if (!material.empty() && std::all_of(material.begin(), material.end(), [&](int m) { return m == material.front(); }))
    pair_law_ = &model_->laws.at(material.front(), material.front());
  ++rebuilds_;
}

void ForceField::build_crowd_list(World& world, const Particles& probe, double margin, std::vector<Pair>& scratch) {
  crowding_.clear();
  if (!model_->fluid.enabled || !model_->fluid.hindered) {
    crowd_list_ = {};
    return;
  }
  const Particles& p = world.particles;
  Particles balls;
  balls.position = probe.position;
  balls.radius.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) balls.radius[i] = CrowdList::probe_radius(model_->fluid, p.radius[i], probe.radius[i]);
  grid_.find_pairs(balls, world.domain, margin, scratch);
  // The search's reach c (r_i + r_j) is more than the balls need, r_i + r_j + (c - 1) max(r_i, r_j)
  // (three times the pairs for one size): the others are dropped.
  const double stretch = model_->fluid.hindered_ball_ratio - 1;
  std::erase_if(scratch, [&](const Pair& q) {
    const double reach = probe.radius[q.i] + probe.radius[q.j] + stretch * std::max(p.radius[q.i], p.radius[q.j]) + margin;
    return norm2(world.domain.separation(probe.position[q.i], probe.position[q.j])) >= reach * reach;
  });
  crowd_list_.build(world, model_->fluid, norm(model_->gravity), scratch);
  crowding_.resize(p.size());
}

void ForceField::grid_meshes(const World& world, const Particles& probe, double margin) {
  if (mesh_grids_.size() == world.walls.size()) return;
  mesh_grids_.assign(world.walls.size(), std::nullopt);
  mesh_reach_.assign(world.walls.size(), 0.0);
  // Cells about as wide as a particle's reach or a triangle, whichever is larger.
  double widest = 0;
  for (double r : probe.radius) widest = std::max(widest, 2 * (r + margin));
  for (std::size_t w = 0; w < world.walls.size(); ++w) {
    const TriangleMesh* mesh = world.walls[w].mesh.get();
    if (!mesh) continue;
    mesh_grids_[w].emplace(*mesh, TriangleGrid::cell_for(*mesh, widest));
    mesh_reach_[w] = turning_reach(world.walls[w]);
  }
}

void ForceField::find_wall_contacts(const World& world, const Particles& probe, double margin,
                                    const std::vector<double>& wall_reach, std::vector<Pair>& out) {
  out.clear();
  if (world.walls.empty()) return;
  grid_meshes(world, probe, margin);
  std::vector<std::vector<Pair>> wall_hits;
  for_each_range(probe.size(), wall_hits, [&](std::size_t begin, std::size_t end, std::vector<Pair>& local) {
    std::vector<std::uint32_t> near;
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t w = 0; w < world.walls.size(); ++w) {
        const Wall& wall = world.walls[w];
        const double reach = wall_reach.empty() ? 0.0 : wall_reach[w];
        const auto particle = static_cast<std::uint32_t>(i);
        if (wall.mesh) {  // the triangles within the margin of touching, from either side
          const Vec3 x = wall.to_mesh(probe.position[i]);
          const double within = probe.radius[i] + margin + reach;
          near.clear();
          mesh_grids_[w]->near(x, within, near);
          for (std::uint32_t t : near)
            if (wall.mesh->may_reach(t, x, within) && norm2(x - wall.mesh->nearest(t, x).point) < within * within)
              local.push_back({particle, world.wall_elements[w] + t});
          continue;
        }
        // Centres in front of the surface (see evaluate_wall) and within the margin of touching.
        const double dist = wall.touch(probe.position[i]).distance;
        if (dist < probe.radius[i] + margin + reach && dist > -margin)
          local.push_back({particle, world.wall_elements.empty() ? static_cast<std::uint32_t>(w) : world.wall_elements[w]});
      }
  });
  for (const auto& local : wall_hits) out.insert(out.end(), local.begin(), local.end());
}

void ForceField::evaluate_pairs(World& world) {
  const auto& contacts = world.contacts.pairs();
  pair_results_.resize(contacts.size(), shifts_, rolls_);
  // Blocks are fixed ranges of the list, the same for any thread count, so each contact is
  // computed by the same instructions (vector lane or scalar tail) whatever the threads.
  const std::size_t blocks = (contacts.size() + kBlock - 1) / kBlock;
  const int threads = threads_for(contacts.size());
  const CurrentState state{world.particles, world.dt};
  for_each_thread(threads, [&](int t) {
    const auto [first, last] = static_range(blocks, t, threads);
    for (std::size_t block = first; block < last; ++block)
      evaluate_pair_block(world, state, ListRange{block * kBlock, std::min((block + 1) * kBlock, contacts.size())},
                          pair_law_, nullptr);
  });
}

void ForceField::evaluate_walls(World& world) {
  const Particles& p = world.particles;
  const auto& contacts = world.contacts.walls();
  wall_results_.resize(contacts.size(), shifts_, rolls_);
  const CurrentState state{p, world.dt};
  if (!world.wall_elements.empty()) touch_walls(world);
  parallel_for(contacts.size(), [&](std::size_t k) { evaluate_wall(world, state, k, nullptr); });
}

void ForceField::touch_walls(World& world) {
  wall_touch_.resize(world.contacts.walls().size());
  parallel_for(world.owned(), [&](std::size_t i) {
    touch_particle_walls(world, i, world.particles.position[i], world.particles.radius[i]);
  });
}

void ForceField::touch_particle_walls(World& world, std::size_t i, const Vec3& x, double reach) {
  // A particle's wall contacts are in the order of their elements, so those with one wall are
  // a run of them: [first, last).
  const std::vector<Contact>& contacts = world.contacts.walls();
  const auto [begin, end] = world.contacts.walls_of(i);
  for (std::uint32_t first = begin; first < end;) {
    const std::uint32_t w = world.wall_of(contacts[first].j);
    std::uint32_t last = first + 1;
    while (last < end && contacts[last].j < world.wall_elements[w + 1]) ++last;
    touch_wall(world, i, w, first, last, x, reach);
    first = last;
  }
}

void ForceField::touch_wall(World& world, std::size_t i, std::uint32_t w, std::uint32_t first, std::uint32_t last,
                            const Vec3& position, double reach) {
  const Wall& wall = world.walls[w];
  if (!wall.mesh) {  // an analytic wall: one element, one contact
    wall_touch_[first] = {wall.touch(position), w, true};
    return;
  }
  std::vector<Contact>& contacts = world.contacts.walls();
  const Vec3 x = wall.to_mesh(position);
  const double r = world.particles.radius[i];
  const std::uint32_t first_element = world.wall_elements[w];
  for (std::uint32_t k = first; k < last; ++k) {
    ElementTouch& e = wall_touch_[k];
    e.wall = w;
    // Surely out of reach, a triangle does not count (TriangleMesh::touch): its contact does not
    // touch whether it counts or not, nor does one at the same point after it (below).
    NearestFeature feature;
    e.counts = touch_triangle(wall, contacts[k].j - first_element, x, reach, e.touch, &feature, &e.spare);
    e.kind = feature.kind, e.feature = feature.index;
    // The same point of the mesh as a contact before it (round-off at a flat mesh's vertex):
    // one contact, the first.
    for (std::uint32_t before = first; before < k && e.counts; ++before)
      e.counts = !(wall_touch_[before].counts && same_contact(wall_touch_[before].touch, e.touch));
  }
  // A flat vertex that none of its triangles counts (their tests disagree to round-off): the
  // first spare counts the plane's touch there, where no contact of the mesh is at that point.
  for (std::uint32_t k = first; k < last; ++k) {
    ElementTouch& e = wall_touch_[k];
    if (!e.spare) continue;
    e.counts = true;
    for (std::uint32_t other = first; other < last && e.counts; ++other)
      e.counts = other == k || !(wall_touch_[other].counts && same_contact(wall_touch_[other].touch, e.touch));
  }
  // A contact that begins takes the history of one that ends on an adjacent triangle (a
  // grain rolling over an edge keeps its spring), which gives it up.
  auto touching_now = [&](std::uint32_t k) {
    return wall_touch_[k].counts && wall_touch_[k].touch.distance < r && wall_touch_[k].touch.distance > 0;
  };
  for (std::uint32_t k = first; k < last; ++k) {
    if (contacts[k].touching || !touching_now(k)) continue;
    for (std::uint32_t k2 = first; k2 < last; ++k2) {
      Contact& ended = contacts[k2];
      if (ended.touching && !touching_now(k2) && wall.mesh->adjacent(contacts[k].j - first_element, ended.j - first_element)) {
        contacts[k].history = ended.history;
        ended.history = {}, ended.touching = false;  // given once
      }
    }
  }
}

void ForceField::accumulate(World& world, double fluid_lead) {
  Particles& p = world.particles;
  // Each particle gathers its own contacts in a fixed order (its partners' ids, then its
  // walls: gather), so the sums are the same bits for every thread count and numbering (and
  // no two threads write the same particle). Listed pairs that do not touch hold zeros and
  // are added without a test (no branch to miss). Only the owned particles: the copies of
  // other processes' particles (World::ghosts) are moved by their owners.
  const std::size_t owned = world.owned();
  const int threads = threads_for(owned);
  std::vector<double> worst(static_cast<std::size_t>(threads), 0.0);
  std::vector<std::uint64_t> touching(static_cast<std::size_t>(threads), 0);
  for_each_thread(threads, [&](int t) {
    const auto [begin, end] = static_range(owned, t, threads);
    double local_worst = 0;
    std::uint64_t local_touching = 0;
    BodyLoad bodies[kBodyBatch];
    for (std::size_t i = begin; i < end; ++i) {
      // Gravity and the still fluid, the fluid at the velocity and spin of the step's end (see
      // compute()), for a batch of particles at a time.
      if ((i - begin) % kBodyBatch == 0) body_loads(p, i, std::min(end, i + kBodyBatch), fluid_lead, false, bodies);
      const BodyLoad& body = bodies[(i - begin) % kBodyBatch];
      Gathered<false> g;
      g.force = body.force;
      g.torque += body.torque;
      gather<false>(world, i, g, nullptr);
      // Every pair is gathered by both its particles, so the largest overlap over the own
      // diameter, taken over all particles, is the largest overlap over the smaller diameter.
      local_worst = std::max(local_worst, g.deepest / (2.0 * p.radius[i]));
      local_touching += static_cast<std::uint64_t>(g.own);  // each pair once, from its first particle
      if (!std::isfinite(g.force.x + g.force.y + g.force.z)) local_worst = INFINITY;
      p.force[i] = g.force;
      p.torque[i] = g.torque;
      p.contact_count[i] = g.count + g.own;
      if (shifts_) p.position[i] = world.domain.wrap(p.position[i] + g.shift);  // model P's contact step
    }
    worst[static_cast<std::size_t>(t)] = local_worst;
    touching[static_cast<std::size_t>(t)] = local_touching;
  });
  for (std::uint64_t c : touching) evaluations_ += c;
  particle_evaluations_ += owned;
  const double max_ratio = *std::max_element(worst.begin(), worst.end());
  if (!(max_ratio <= model_->overlap_limit)) report_overlap(world, false);
}

ContactTotals ForceField::totals(const World& world) const {
  ContactTotals totals;
  ExactSum elastic_energy;
  auto add = [&](const std::vector<Contact>& contacts, const Results& results, bool is_wall) {
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      if (!contacts[k].touching) continue;
      ++totals.contacts;
      elastic_energy += results.entry[k].energy;
      totals.max_overlap_ratio = std::max(totals.max_overlap_ratio, overlap_ratio(world, k, is_wall));
    }
  };
  add(world.contacts.pairs(), pair_results_, false);
  add(world.contacts.walls(), wall_results_, true);
  totals.elastic_energy = elastic_energy.value();
  return totals;
}

double ForceField::wall_load(const World& world, std::size_t wall) const {
  ExactSum load;
  const auto& contacts = world.contacts.walls();
  const Wall& w = world.walls[wall];
  // A mesh has no one normal: its load is along the way it moves now (none while still).
  const Vec3 along = !w.mesh ? w.normal : (w.velocity == Vec3{} ? Vec3{} : w.velocity / norm(w.velocity));
  for (std::size_t k = 0; k < contacts.size(); ++k)
    if (contacts[k].touching && world.wall_of(contacts[k].j) == wall) load += dot(wall_results_.entry[k].force_i, along);
  return load.value();
}

bool ForceField::evaluated(const World& world) const {
  return pair_results_.entry.size() >= world.contacts.pairs().size() &&
         wall_results_.entry.size() >= world.contacts.walls().size();
}

double ForceField::overlap_ratio(const World& world, std::size_t k, bool is_wall) const {
  const Particles& p = world.particles;
  if (is_wall) return wall_results_.entry[k].delta / (2.0 * p.radius[world.contacts.walls()[k].i]);
  const Contact& c = world.contacts.pairs()[k];
  return pair_results_.entry[k].delta / (2.0 * std::min(p.radius[c.i], p.radius[c.j]));
}

namespace {

// How many steps of dt a collision of contact c's pair lasts at the speed of the one grain
// relative to the other (or to the wall) now.
double steps_per_contact(const World& world, const LawTable& laws, const Contact& c, bool wall) {
  const Particles& p = world.particles;
  const std::size_t a = c.i, b = c.j;
  const double m_eff = wall ? p.mass[a] : p.mass[a] * p.mass[b] / (p.mass[a] + p.mass[b]);
  const double r_eff = wall ? p.radius[a] : p.radius[a] * p.radius[b] / (p.radius[a] + p.radius[b]);
  const Wall* w = wall ? &world.walls[world.wall_of(c.j)] : nullptr;
  const double speed = norm(p.velocity[a] - (w ? w->surface_velocity_at(p.position[a]) : p.velocity[b]));
  const int other = w ? w->material : p.material[b];
  return contact_time(laws.at(p.material[a], other).normal, m_eff, r_eff, speed) / world.dt;
}

}  // namespace

void ForceField::report_overlap(const World& world, bool block_steps) const {
  const Particles& p = world.particles;
  const Contact* worst = nullptr;
  bool wall = false;
  double ratio = -1;
  auto scan = [&](const std::vector<Contact>& contacts, const Results& results, bool is_wall) {
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      const Vec3& f = results.entry[k].force_i;
      const double r = std::isfinite(f.x + f.y + f.z) ? overlap_ratio(world, k, is_wall) : INFINITY;
      if (contacts[k].touching && !(r <= ratio)) ratio = r, worst = &contacts[k], wall = is_wall;
    }
  };
  scan(world.contacts.pairs(), pair_results_, false);
  scan(world.contacts.walls(), wall_results_, true);
  // Before the first evaluation succeeded the state is the one the run started from. A fixed
  // step evaluates at its end (the clock has advanced); a block step at its block time
  // (world.time), within the step under way (the counter advances after its last block time).
  const bool initial = !started_;
  std::ostringstream msg;
  if (block_steps && !initial) msg << "step " << world.step + 1 << ", block time " << world.time << " s: ";
  else msg << "step " << world.step << ", t = " << world.time << " s: ";
  std::string model;      // the normal model of the worst contact
  std::string_view hint;  // what a non-finite force of it means
  if (worst) {
    const std::size_t a = worst->i, b = worst->j;
    const std::uint32_t w = wall ? world.wall_of(worst->j) : 0;
    const int mat_b = wall ? world.walls[w].material : p.material[b];
    const NormalModel& normal = model_->laws.at(p.material[a], mat_b).normal;
    model = label_of(normal);
    hint = when_not_finite(normal);
    msg << "contact between particle id " << p.id[a] << " and "
        << (wall ? "wall " + std::to_string(w) +
                       (world.walls[w].mesh ? " (triangle " + std::to_string(worst->j - world.wall_elements[w]) + ")" : "")
                 : "particle id " + std::to_string(p.id[b]))
        << " (normal model " << model
        << ") has overlap/diameter " << ratio;
  } else {
    msg << "a particle force is not finite";
  }
  if (!std::isfinite(ratio)) msg << " (a non-finite force" << (hint.empty() ? "" : ": ") << hint << ")";
  msg << " (limit " << model_->overlap_limit << ", simulation.overlap_limit); ";
  // Before the first step the cause is the input, whatever dt is.
  if (initial && world.step == 0)
    msg << "this is the initial state, before any time step: the input places particles too deep in each other or "
           "in a wall (check their positions and diameters, and the walls; dt is not the cause)";
  else if (block_steps)
    msg << "with block steps each particle's step is dt/2^level, set by the step rules: a step was too long for this"
           " contact; tighten [simulation.block_steps] (kappa_c for contacts, eta_gap for approaching grains,"
           " eta_damping for dashpots), whatever dt is";
  else if (const double steps = worst ? steps_per_contact(world, model_->laws, *worst, wall) : 0; steps >= kStepsPerContact)
    msg << "the contact lasts about " << steps << " steps of dt = " << world.dt
        << " s at the pair's speed now, so dt is not the cause (dt/4 stops the same way): the overlap is physical, the "
           "grains are too soft for this load or impact speed; use a stiffer material (youngs_modulus) or a larger "
           "simulation.overlap_limit";
  else
    msg << "the time step " << world.dt << " s is probably too large for this stiffness and impact speed: try dt/4";
  throw NumericalError(msg.str());
}

}  // namespace tsubu
