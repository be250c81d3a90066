// Computes the force and torque on every particle of a World under a Model: gravity, the
// still fluid's forces (Model::fluid) and all pair and wall contacts (Model::laws).
#pragma once
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "tsubu/fluid/crowding.hpp"
#include "tsubu/model/model.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/search/triangle_grid.hpp"
#include "tsubu/world/kinematics.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// Totals of the last evaluation, for the time series.
struct ContactTotals {
  std::size_t contacts = 0;         // pair + wall contacts
  double elastic_energy = 0;        // J, stored in the normal springs
  double max_overlap_ratio = 0;     // largest overlap / smaller diameter
};

// A touching contact as the last evaluation left it, for output (contact network frames,
// tsubu export). `j` is the partner's particle index (a pair's i is its particle with the
// smaller id: the contact list's orientation), or the wall's index when `wall`.
struct ContactRecord {
  std::uint32_t i = 0, j = 0;
  bool wall = false;
  Vec3 normal_force, tangential_force;  // N, on particle i; their sum is the contact's force on i
  double overlap = 0;                   // m
  ContactHistory history;               // the model's memory (tangential spring, normal slots), from i
};

// Block steps: how an evaluation bounds the next step of each particle from its contacts
// (docs/integrators.md, step rules). A touching contact allows kappa_c times the shorter
// of its collision time at the current approach speed (Eq. 20, speed floored at u_floor)
// and half a period of its current linear-equivalent stiffness; a particle in touch at most
// eta_damping over a bound on its dashpots' fastest decay rate (see compute_active); an
// approaching listed pair allows eta_gap times the time to close its gap, but never less
// than its contact step. The values (and their defaults) are BlockStepRules'.
struct ContactStepRules {
  double kappa_c = 0;
  double eta_gap = 0;
  double u_floor = 0;  // m/s
};

// What a block-step evaluation returns beside forces and torques, per particle (only the
// active particles' entries are written).
struct EvaluationRates {
  std::vector<Vec3> force, torque;  // dF/dt (N/s) and dT/dt (N m/s)
  std::vector<double> step_bound;   // s, the contacts' and gaps' limit on the next step
  // 1/s: a bound on the fastest decay rate of the dashpots around the particle (the block
  // Gershgorin sum of ForceField::compute_active), for the integrator's dashpot rule.
  std::vector<double> damping_rate;
  // s: when exactly one contact of the particle began since its last evaluation (and none
  // ended), how long ago (its overlap over its rate of overlap); when exactly one ended (and
  // none began), how long ago (its gap over its rate of opening); 0 otherwise. The corrector
  // locates the event inside the step with them (BlockHermite::correct). Both are read from
  // the evaluation now and the touching flag, so that a resumed run finds them alike.
  std::vector<double> touched_for, released_for;

  void resize(std::size_t n) {
    force.resize(n), torque.resize(n), step_bound.resize(n), damping_rate.resize(n), touched_for.resize(n),
        released_for.resize(n);
  }
};

// The body forces on a particle: gravity and the still fluid's (ForceField::body_loads).
struct BodyLoad {
  Vec3 force, torque;
};

// One contact's result of the last evaluation, as seen from its particle i (a pair's with the
// smaller id): the force on i, n x F_t (n from j, or the wall, to i), the overlap (> 0 when
// touching) and the elastic energy stored.
struct ContactResult {
  Vec3 force_i, n_x_ft;
  double delta = 0, energy = 0;
};

// The particles of other processes, in a run split among them (ranks/decomposition.hpp):
// brought up to date before every evaluation.
class ForceField;

class Neighbourhood {
 public:
  virtual ~Neighbourhood() = default;
  // Refreshes the copies of the other processes' particles in world (World::ghosts), or
  // rearranges the particles among the processes; true when it did (the lists must be
  // built again). `lost`: this process lost a particle in the step's drift (ParticleLost),
  // and calls this instead of an evaluation. Throws StepAbandoned on every process when
  // any process lost one, before anything is rearranged.
  virtual bool update(World& world, bool lost) = 0;
  // The elementwise "or" of `flags` over the processes (the same length on each).
  virtual void agree_any(std::vector<char>& flags) const = 0;
  // `arrivals`, the same particles on every process (grains that join the run between
  // steps, ForceField::welcome'd), join it: each process takes those in its subdomain and the
  // particles are arranged again (the next update returns true). `forces`: the field whose
  // last evaluation the contacts' results until the next one are (outputs read them).
  virtual void add(World& world, Particles arrivals, const ForceField& forces) = 0;
  // The particles with ids `ids` (sorted; the same on every process) leave the run: each
  // process drops them, its own and its copies, with their contacts, and the particles are
  // arranged again (the next update returns true).
  virtual void remove(World& world, const std::vector<std::int64_t>& ids) = 0;
  // Every process's `bytes`, by process, on every process.
  virtual std::vector<std::string> gather_all(const std::string& bytes) = 0;
};

// Neighbour lists (world.contacts: pairs and walls within `skin` of touching) are rebuilt,
// carrying every history over, once some particle has moved more than skin/2 since the last
// build; in between, each step only evaluates the listed pairs.
class ForceField {
 public:
  // The list entries of one pair block: the lanes of the law loop (forces/evaluate.hpp).
  static constexpr std::size_t kBlock = 32;

  // The physics the field evaluates; `model` must outlive the field.
  explicit ForceField(const Model& model)
      : model_(&model),
        without_rates_(model.laws.without_rates()),
        shifts_(model.laws.corrects_positions()),
        rolls_(model.laws.resists_rolling()) {}
  const Model& model() const { return *model_; }

  // Evaluates every touching contact and sums forces and torques (with gravity) into
  // world.particles. Throws NumericalError when an overlap exceeds Model::overlap_limit or
  // a force is not finite. The still fluid's forces are taken at the velocity and spin
  // v + fluid_lead F/m, w + fluid_lead T/I with the previous force and torque: velocity
  // Verlet, whose velocities are half a step behind here, passes dt/2 (its fluid forces
  // are then second order in dt; at the half-step velocity they are first order).
  void compute(World& world, double fluid_lead = 0);

  // Block steps (the same lists, contact evaluation and gather, run on dual numbers):
  // evaluates the active particles at the predictor's time from the predicted state of every
  // particle they touch, with the exact rates of every force and torque: gravity and
  // contacts; the fluid's forces are left to the integrator (they depend on the corrected
  // velocity). A contact is evaluated once, from its first active particle; its history
  // advances by the time since the later of its particles' last evaluations (their shared
  // step). The lists are the stepper's to rebuild (rebuild_at).
  // Throws std::invalid_argument when a law has no rates (LawTable::without_rates).
  void compute_active(World& world, const Predictor& kin, const std::vector<std::uint32_t>& active,
                      const std::vector<char>& is_active, const ContactStepRules& rules, EvaluationRates& out);
  // compute_active's evaluation for block steps shared among processes (BlockHermite::
  // share_among): the active particles `here` marks, listed in `mine`, of those is_active
  // marks. A contact is evaluated here from its first active particle here (so a pair whose
  // particles are active on two processes, on both, alike). Returns the deepest overlap over
  // diameter of those particles' contacts (infinite for a force not finite) for
  // check_overlaps, once every process's evaluation is in (take_active).
  double evaluate_active(World& world, const Predictor& kin, std::span<const std::uint32_t> mine,
                         const std::vector<char>& is_active, const std::vector<char>& here, const ContactStepRules& rules,
                         EvaluationRates& out);
  // Throws NumericalError, naming the deepest contact, when `worst` (evaluate_active's)
  // exceeds Model::overlap_limit.
  void check_overlaps(const World& world, double worst) const;
  // What the last evaluate_active found for the particles `mine` (of those is_active marks),
  // appended to `out` for the other processes: each particle's force, torque, contact count
  // and crowding; each contact evaluated for them, once (the pairs of their first particle,
  // and of their second where the first is not active) with its touching flag, history,
  // result and rates; the contact evaluations counted. take_active reads it into this
  // process's copy from bytes[at ...).
  void pack_active(const World& world, std::span<const std::uint32_t> mine, const std::vector<char>& is_active,
                   std::string& out) const;
  void take_active(World& world, std::string_view bytes, std::size_t& at);
  // Block steps: the change of the active particles' contact forces and torques when the
  // velocities and spins change by dv, dw (per particle, zero for the others) at the last
  // evaluation's positions: the dashpots' linear response -eta_n (du.n) n - eta_t du_t to the
  // change du of each touching contact's relative velocity, and model EPSD's rolling dashpot
  // -C_r dw_r to the change of the relative rolling velocity. The same map takes a change of
  // accelerations to the change of the forces' rates. Written to df, dtorque (active entries).
  void dashpot_response(const World& world, const std::vector<std::uint32_t>& active, const std::vector<Vec3>& dv,
                        const std::vector<Vec3>& dw, std::vector<Vec3>& df, std::vector<Vec3>& dtorque) const;
  // Block steps: new lists from the given positions, each particle i listed with everything
  // within skin + reach[i] (+ reach of the partner, or wall_reach of a wall) of touching;
  // valid while each particle stays within reach[i] + skin/2 of its position here and each
  // wall within wall_reach + skin/2 of its place now.
  void rebuild_at(World& world, const std::vector<Vec3>& positions, const std::vector<double>& reach,
                  const std::vector<double>& wall_reach);
  // The particles appended to `p` since the last call (every particle at the first call) get
  // their translational mass m + C_M rho_f V, the inertia the integrators divide forces by
  // (Particles::translational_mass; Fluid::added_mass_of): the one place it is set. compute()
  // and compute_active() call it first; whoever adds particles between steps calls it
  // before the next kick.
  void admit_new_particles(Particles& p);
  // Grains that join a run between steps, those of `p` from `first` on: their translational
  // mass, and as their force and torque the body load of a lone grain (no contact yet;
  // fluid_lead 0), which the next kick reads; no contacts.
  void welcome(Particles& p, std::size_t first) const;
  // The body forces on particles first, ..., last - 1 of `p` (out[k] for particle first + k):
  // gravity m g and the still fluid's buoyancy, drag and lift with their torque
  // (Model::fluid; none without a fluid), the drag hindered by the crowding the last
  // evaluation found (a grain that joined since, or all with `lone`: none). The fluid's are
  // taken at the velocity and spin v + fluid_lead F/m, w + fluid_lead T/I with the particle's
  // force and torque now (see compute()). The one place they are added up, for the fixed-step
  // evaluation (a batch of grains at a time: fluid_loads) and for grains that join a run
  // (welcome: fluid_lead 0, lone).
  void body_loads(const Particles& p, std::size_t first, std::size_t last, double fluid_lead, bool lone,
                  BodyLoad* out) const;
  // The world's particles were renumbered (sort_spatially) or some removed (Outflow): the
  // contact records follow their contacts; the lists are rebuilt at the next evaluation.
  void renumbered(const World& world);
  // A run split among processes: `n` (which must outlive the field) updates the other
  // processes' particles before every evaluation; null for a run in one process.
  void set_neighbourhood(Neighbourhood* n) { neighbourhood_ = n; }
  bool distributed() const { return neighbourhood_ != nullptr; }
  Neighbourhood* neighbourhood() const { return neighbourhood_; }
  double skin() const { return skin_; }
  // Whether a wall has moved (a mesh: moved and turned its farthest vertex) by more than half
  // the skin since the lists were built.
  bool walls_moved(const World& world) const;
  // The neighbour-list margin for a world: Model::skin, or a tenth of the smallest diameter.
  double skin_of(const World& world) const;
  // The neighbour-list margin for particles whose smallest radius is `smallest_radius`.
  double skin_for(double smallest_radius) const { return model_->skin > 0 ? model_->skin : 0.2 * smallest_radius; }
  // The largest distance between the centres of two particles that act on each other, in
  // units of the largest radius: 2 for contacts, c + 1 where hindered settling measures the
  // solid fraction in a ball of c radii around each grain (CrowdList).
  double reach_per_radius() const;

  // Contacts, elastic energy and largest overlap of the last evaluation (a pass over all
  // contacts: call it for output, not every step).
  ContactTotals totals(const World& world) const;
  // Every touching contact of the last evaluation: pairs in list order, then walls (a pass
  // over all contacts: call it for output). The tangential force is recovered from the
  // stored n x F_t with the normal of the current positions; the normal force is the rest
  // of the stored force, so the two add up to it exactly.
  std::vector<ContactRecord> touching_contacts(const World& world) const;
  // Force the particles exert on wall `wall` along minus its normal (positive when pushed),
  // N, from the last evaluation; on a mesh, against its motion now (positive when they resist it).
  double wall_load(const World& world, std::size_t wall) const;
  // The result of the last evaluation of entry k of world.contacts' pair or wall list.
  const ContactResult& pair_result(std::size_t k) const { return pair_results_.entry[k]; }
  const ContactResult& wall_result(std::size_t k) const { return wall_results_.entry[k]; }
  // The results of contacts evaluated elsewhere, for the outputs above: a run split among
  // processes gathered on one (Decomposition::gathered). One per entry of world.contacts'
  // lists.
  void adopt_results(std::vector<ContactResult> pairs, std::vector<ContactResult> walls) {
    pair_results_.entry = std::move(pairs), wall_results_.entry = std::move(walls);
  }
  // Whether the current lists have been evaluated (not yet after a resume from a checkpoint,
  // until the next step): touching_contacts() is then complete.
  bool evaluated(const World& world) const;
  // Whether some law of the model resists rolling (its contacts then carry a rolling torque,
  // and a rolling spring under model epsd).
  bool resists_rolling() const { return rolls_; }
  // Hindered settling (Fluid::hindered): the solid fraction around particle i, its rate and
  // exponent as the last evaluation of i found them (a lone grain's without hindrance).
  const Crowding& crowding(std::size_t i) const { return i < crowding_.size() ? crowding_[i] : kLone; }
  std::uint64_t evaluations() const { return evaluations_; }  // contact force evaluations
  // Particle force evaluations of compute(): the particles (owned) summed over its calls, so
  // that a run whose particle count grows (an inflow) counts each grain from its entry on.
  std::uint64_t particle_evaluations() const { return particle_evaluations_; }
  std::uint64_t rebuilds() const { return rebuilds_; }  // neighbour-list builds
  // Resuming from a checkpoint: the counters continue; the lists are rebuilt on the next
  // compute from world's contact lists (results do not depend on when lists are built).
  struct Counters {
    std::uint64_t evaluations = 0, particle_evaluations = 0, rebuilds = 0;
  };
  Counters counters() const { return {evaluations_, particle_evaluations_, rebuilds_}; }
  void restore_counters(const Counters& c) {
    evaluations_ = c.evaluations, particle_evaluations_ = c.particle_evaluations, rebuilds_ = c.rebuilds;
  }

 private:
  // Per-contact results, one array per quantity (zeros for pairs that do not touch);
  // delta > 0 marks a touching contact. The torques and overlap ratios are not stored: each
  // particle makes them from n x F_t, the overlap and its own radius (64 bytes a contact,
  // not 104).
  // shift_i/j, the position corrections of models P and F, exist only when a law uses them;
  // rolling_i, the rolling torque on i (j takes it negated), only when a law resists rolling.
  struct Results {
    using Entry = ContactResult;  // together: the gather reads a partner's contact from one place
    std::vector<Entry> entry;
    std::vector<Vec3> shift_i, shift_j, rolling_i;
    void resize(std::size_t n, bool shifts, bool rolls);
    // Each entry follows its contact into new lists (ContactList::follow).
    void follow(const std::vector<std::uint32_t>& origin);
    void set(std::size_t k, const Vec3& f, const Vec3& n_x_f_t, double overlap, double e) { entry[k] = {f, n_x_f_t, overlap, e}; }
    // Torque on a particle of radius r from contact k (the lever arm ends mid-overlap).
    Vec3 torque(std::size_t k, double r) const { return -(r - 0.5 * entry[k].delta) * entry[k].n_x_ft; }
  };
  // Rates of the block-step evaluations, per contact (the results' companions), filled by
  // the evaluation's rate channel.
  struct Rates {
    Vec3 force_i, n_x_ft;  // d/dt of ContactResult's force_i and n_x_ft
    double delta = 0;      // d(overlap)/dt
    double step_bound = 0; // s, see ContactStepRules
    Vec3 n;                // unit normal from j to i (dashpot_response)
    double damping = 0, tangential_damping = 0;  // eta_n, eta_t now, N s/m
    // A contact that began since its last evaluation: how long ago, delta / (d delta/dt)
    // (EvaluationRates::touched_for). One that ended: how long ago, gap / (d gap/dt)
    // (EvaluationRates::released_for). 0 for every other.
    double touched_for = 0, released_for = 0;
    // With rolling resistance: d/dt of Results::rolling_i and the rolling dashpot's C_r now
    // (N m s/rad; 0 without one or at its cap).
    Vec3 rolling_i = {};
    double rolling_damping = 0;
  };
  const Model* model_;
  std::string without_rates_;  // LawTable::without_rates of the model, found once
  PairSearch grid_;
  static constexpr Crowding kLone{};
  CrowdList crowd_list_;              // built with the lists when the fluid hinders settling
  std::vector<Crowding> crowding_;    // per particle
  Results pair_results_, wall_results_;
  std::vector<Rates> pair_rates_, wall_rates_;
  std::vector<Vec3> built_at_;  // positions at the last build
  bool shifts_ = false;         // some law corrects positions
  bool rolls_ = false;          // some law resists rolling
  // The law of every listed pair when the grains are all of one material (set at each build;
  // the pairs are then evaluated in vector lanes), else null: each pair takes its own.
  const PairLaw* pair_law_ = nullptr;
  std::vector<Vec3> walls_built_at_;  // wall points at the last build
  // Meshes (World::wall_elements): per wall its triangles' grid, for a mesh (built at the
  // first list build). Per wall contact, where its particle touches its element at the last
  // fixed-step evaluation, the element's wall, and whether the contact counts there
  // (world/mesh.hpp).
  struct ElementTouch {
    WallTouch touch;
    std::uint32_t wall = 0;
    bool counts = false;
    bool spare = false;  // on a mesh, a flat edge or vertex the triangle does not own (TriangleMesh::touch)
    NearestFeature::Kind kind = NearestFeature::face;  // on a mesh, the nearest feature (for the rates)
    std::uint32_t feature = 0;
  };
  std::vector<std::optional<TriangleGrid>> mesh_grids_;
  std::vector<double> mesh_reach_;  // m, per wall: a turning mesh's farthest vertex from its axis
  std::vector<std::pair<double, double>> walls_turn_at_;  // per wall: a turning mesh's (cos, sin) at the last build
  std::vector<ElementTouch> wall_touch_;
  double skin_ = 0;
  std::size_t admitted_ = 0;  // particles whose translational mass is set
  std::uint64_t evaluations_ = 0, particle_evaluations_ = 0, rebuilds_ = 0;
  std::uint64_t active_evaluations_ = 0;  // the contact evaluations of the last evaluate_active
  bool started_ = false;  // an evaluation has succeeded: the run has left its initial state
  Neighbourhood* neighbourhood_ = nullptr;
  bool keeps_records_ = false;  // the lists' records outlive a list change (block steps' builds)

  bool needs_rebuild(const World& world) const;
  void record_walls(const World& world);  // where the walls are at a build (walls_moved)
  void rebuild(World& world);
  // The lists from `probe` (positions and radii, grown by each particle's reach) and the
  // margin; histories carried over, and with keep_records the contact records and rates too
  // (block steps: a contact keeps the results of its last evaluation until its particles
  // are next active; fixed steps evaluate every contact after a build).
  void build_lists(World& world, const Particles& probe, double margin, const std::vector<double>& wall_reach,
                   bool keep_records);
  void follow_lists(const ContactList& contacts);
  // wall_reach: per wall, added to the margin (empty: none).
  void find_wall_contacts(const World& world, const Particles& probe, double margin, const std::vector<double>& wall_reach,
                          std::vector<Pair>& out);
  void grid_meshes(const World& world, const Particles& probe, double margin);
  // With meshes, before the wall contacts are evaluated: where each touches (wall_touch_), one
  // of a particle's contacts at the same point of a mesh counted, and a contact that begins
  // on a mesh taking the history of one of the same mesh that ends (a grain rolling from
  // triangle to triangle keeps its spring). touch_walls does it for every particle at its
  // position (fixed steps), touch_particle_walls for particle i centred at x, asking about
  // triangles within `reach` of x (INFINITY: every listed one, for the step rules' gaps),
  // touch_wall for its contacts first .. last - 1 with wall w.
  void touch_walls(World& world);
  void touch_particle_walls(World& world, std::size_t i, const Vec3& x, double reach);
  void touch_wall(World& world, std::size_t i, std::uint32_t w, std::uint32_t first, std::uint32_t last, const Vec3& x,
                  double reach);
  // The wall of wall contact k: its element's with meshes (found by touch_walls), else the
  // element itself.
  std::uint32_t wall_of_contact(const World& world, std::size_t k) const {
    return world.wall_elements.empty() ? world.contacts.walls()[k].j : wall_touch_[k].wall;
  }
  // The crowd list from the same probe (each ball's reach added to the probe radii).
  void build_crowd_list(World& world, const Particles& probe, double margin, std::vector<Pair>& scratch);
  // The one contact evaluation (forces/evaluate.hpp), on the number type of `State`: a fixed
  // step on double (CurrentState: the particles' arrays), a block step on Dual
  // (PredictedState: the predictor's kinematics), where the rate channel also fills the
  // Rates under `rules` (null for fixed steps). Pairs go in blocks of at most kBlock list
  // entries, evaluated with `shared` when every pair of the list has that law (pair_law_),
  // else each with its own; walls one at a time, with their law.
  template <class State, class Entries>
  void evaluate_pair_block(World& world, const State& state, const Entries& entries, const PairLaw* shared,
                           const ContactStepRules* rules);
  // Wall contact k under its law (the grain's material against the wall's), on the State's
  // number type.
  template <class State>
  void evaluate_wall(World& world, const State& state, std::size_t k, const ContactStepRules* rules);
  template <class State, class Normal, class Tangential, class Rolling>
  void evaluate_wall(World& world, const State& state, std::size_t k, const Normal& normal, const Tangential& tangential,
                     const Rolling& rolling, const ContactStepRules* rules);
  // Fixed steps: every listed pair and wall.
  void evaluate_pairs(World& world);
  void evaluate_walls(World& world);
  void accumulate(World& world, double fluid_lead);
  // What particle i gathers from its evaluated contacts, in ContactList::for_each_contact_of
  // order (so the sums are the same bits for any thread count): force and torque (added to
  // what `g` holds), the contact counts and the deepest overlap; for fixed steps the position
  // corrections of models P and F; WithRates, also the forces' and torques' rates, the contacts'
  // step bound, the dashpots' damping over mass and the contacts evaluated from i (is_active:
  // a pair whose first particle is active was evaluated from it).
  struct Sums {
    Vec3 force, torque, shift;
    int count = 0, own = 0;  // touching contacts where i is the pair's second, first or a wall's particle
    double deepest = 0;      // m
  };
  struct RateSums : Sums {
    Vec3 force_rate, torque_rate;
    double bound = std::numeric_limits<double>::infinity(), damping_over_mass = 0;
    std::uint64_t evaluated = 0;
    int began = 0, ended = 0;  // contacts that began or ended since their last evaluation
    double touched_for = 0, released_for = 0;  // s, the Rates' of the last of them
  };
  template <bool WithRates>
  using Gathered = std::conditional_t<WithRates, RateSums, Sums>;  // the fixed steps' sums carry no rates
  template <bool WithRates>
  [[gnu::always_inline]] void gather(const World& world, std::size_t i, Gathered<WithRates>& g,
                                     const std::vector<char>* is_active) const;
  // Overlap over the smaller diameter of contact k (is_wall: a wall contact).
  double overlap_ratio(const World& world, std::size_t k, bool is_wall) const;
  // block_steps: the block-step evaluation (each particle's step dt/2^level, not dt).
  [[noreturn]] void report_overlap(const World& world, bool block_steps) const;
};

}  // namespace tsubu
