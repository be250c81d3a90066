#include "tsubu/sim/simulation.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "tsubu/core/error.hpp"
#include "tsubu/world/spatial_sort.hpp"

namespace tsubu {

Simulation::Simulation(World world, Model model, Integrator integrator, const BlockStepRules& block_steps)
    : model_(std::make_unique<const Model>(std::move(model))), world_(std::move(world)), integrator_(integrator) {
  if (integrator_ == Integrator::block_hermite) block_ = std::make_unique<BlockHermite>(block_steps);
  world_.index_wall_elements();  // the walls' contact partners (a mesh: its triangles)
  if (world_.domain.any_open()) outflow_.emplace();
}

void Simulation::feed(InflowFeed inflow) {
  if (outflow_) outflow_->count_inflow_from(inflow.first_id());
  inflow_.emplace(std::move(inflow));
}

double Simulation::inflow_mass_entered() const {
  if (!inflow_) return 0;
  return inflow_->mass_in_box(world_) + (outflow_ ? outflow_->totals().inflow_mass : 0.0);
}

void Simulation::start() {
  if (block_) {
    block_->start(world_, forces_);
  } else {
    // The first evaluation's contacts see each wall's motion of the stretch that holds the
    // start (as block steps' walls_at; each drift sets it for its own step): a grain touching
    // a moving wall at t = 0 felt it standing still.
    for (Wall& w : world_.walls) w.motion_during(world_.time);
    evaluate(0);
  }
  admit_inflow();
}

std::exception_ptr Simulation::step_to_its_end() {
  std::exception_ptr failure;
  if (block_) {
    if (sort_due()) renumber();
    try {
      block_->advance(world_, forces_);
      remove_departed_at_block_end();
    } catch (const NumericalError&) {  // every process sharing the block steps fails alike
      failure = std::current_exception();
    }
  } else {
    try {
      advance(integrator_, world_, [&](double fluid_lead) {
        try {
          evaluate(fluid_lead);
        } catch (const NumericalError&) {  // the force check, after every particle's force is set
          failure = std::current_exception();
        }
      });
    } catch (const ParticleLost&) {  // the drift's, before the evaluation
      Neighbourhood* split = forces_.neighbourhood();
      if (!split) throw;
      failure = std::current_exception();
      announce_loss(*split);
    } catch (const StepAbandoned&) {  // another process's drift lost a particle
      failure = std::current_exception();
    }
  }
  if (!failure) admit_inflow();
  return failure;
}

void Simulation::announce_loss(Neighbourhood& split) {
  // The step's first exchange, where the other processes are in their evaluation (evaluate):
  // the departures' with open faces, else the ghosts' refresh. It ends the step everywhere.
  try {
    if (outflow_) remove_departed_among_processes(split, true);
    else split.update(world_, true);
  } catch (const StepAbandoned&) {
    return;
  }
  throw std::logic_error("a split run went on after a process lost a particle");
}

void Simulation::evaluate(double fluid_lead) {
  if (outflow_) {
    forces_.admit_new_particles(world_.particles);  // every particle's translational mass moves with it
    if (Neighbourhood* split = forces_.neighbourhood()) remove_departed_among_processes(*split, false);
    else if (outflow_->remove_departed(world_)) forces_.renumbered(world_);
  }
  if (sort_due()) renumber();
  forces_.compute(world_, fluid_lead);
}

// Block steps: a grain may cross an open face in the middle of a step, on its own shorter
// step; it flies on (beyond the face, where nothing touches it but grains it still touches)
// until the step's end, when every grain is at the same time and it is removed, as the fixed
// steps remove it before their next evaluation.
void Simulation::remove_departed_at_block_end() {
  if (!outflow_) return;
  forces_.admit_new_particles(world_.particles);  // every particle's translational mass moves with it
  std::vector<std::uint32_t> kept;
  if (!outflow_->remove_departed(world_, &kept)) return;
  forces_.renumbered(world_);
  block_->particles_removed(world_, forces_, kept);
}

void Simulation::remove_departed_among_processes(Neighbourhood& split, bool lost) {
  static_assert(std::is_trivially_copyable_v<Departure>);
  // Each process's word: whether its drift lost a particle (the step then ends on every
  // process, StepAbandoned), then its departures.
  std::string mine_bytes(1, lost ? '\1' : '\0');
  if (!lost) {
    const std::vector<Departure> mine = Outflow::departures(world_, world_.owned());
    mine_bytes.append(reinterpret_cast<const char*>(mine.data()), mine.size() * sizeof(Departure));
  }
  const std::vector<std::string> words = split.gather_all(mine_bytes);
  for (const std::string& bytes : words)
    if (bytes[0] != '\0') throw StepAbandoned();
  std::vector<Departure> gone;
  for (const std::string& bytes : words) {
    const std::size_t first = gone.size(), count = (bytes.size() - 1) / sizeof(Departure);
    gone.resize(first + count);
    if (count > 0) std::memcpy(gone.data() + first, bytes.data() + 1, count * sizeof(Departure));
  }
  if (gone.empty()) return;  // the same on every process
  std::sort(gone.begin(), gone.end(), [](const Departure& a, const Departure& b) { return a.id < b.id; });
  outflow_->record(gone);
  std::vector<std::int64_t> ids;
  for (const Departure& d : gone) ids.push_back(d.id);
  split.remove(world_, ids);
}

bool Simulation::sort_due() const {
  const std::int64_t every = model_->search.sort_every;
  return every > 0 && world_.step % every == 0 && !forces_.distributed();  // processes order their own particles
}

void Simulation::renumber() {
  forces_.admit_new_particles(world_.particles);  // every particle's translational mass moves with it
  const std::vector<std::uint32_t> order = sort_spatially(world_);  // order[new] = old
  forces_.renumbered(world_);
  if (block_) block_->renumber(order);
}

void Simulation::admit_inflow() {
  if (!inflow_) return;
  if (Neighbourhood* split = forces_.neighbourhood()) {  // every process admits the same grains
    Particles arrivals;
    inflow_->admit(world_, arrivals, [split](std::vector<char>& taken) { split->agree_any(taken); });
    if (arrivals.size() == 0) return;
    forces_.welcome(arrivals, 0);
    split->add(world_, std::move(arrivals), forces_);
    return;
  }
  const std::size_t first = world_.particles.size();
  inflow_->admit(world_);
  if (world_.particles.size() > first) particles_added(first);
}

void Simulation::advance_to(std::int64_t step) {
  while (world_.step < step) this->step();
}

void Simulation::particles_added(std::size_t first) {
  if (block_) {
    block_->particles_added(world_, forces_, first);
    return;
  }
  forces_.admit_new_particles(world_.particles);
  forces_.welcome(world_.particles, first);
}

std::pair<double, double> Simulation::radius_range() const {
  const std::vector<double>& r = world_.particles.radius;
  double smallest = r.empty() ? 0.0 : *std::min_element(r.begin(), r.end());
  double largest = r.empty() ? 0.0 : *std::max_element(r.begin(), r.end());
  if (inflow_) {
    const SizeDistribution& sizes = inflow_->sizes();
    smallest = r.empty() ? 0.5 * sizes.smallest() : std::min(smallest, 0.5 * sizes.smallest());
    largest = std::max(largest, 0.5 * sizes.largest());
  }
  return {smallest, largest};
}

std::uint64_t Simulation::particle_force_evaluations() const {
  return block_ ? block_->particle_evaluations() : forces_.particle_evaluations();
}

}  // namespace tsubu
