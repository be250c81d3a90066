// Block-step Hermite integrator (Sota & Watanabe section 3.1; docs/integrators.md): a
// fourth-order Hermite predictor-evaluate-corrector scheme in which every particle has its
// own time and its own step dt / 2^level. Time is an integer count of ticks dt / 2^L (L the
// finest level), so block times are exact. At each block time the active particles (those
// whose step ends there) are evaluated from the predicted state of everything they touch
// and corrected; the others are only predicted. Particles in touch step on levels at most
// `level_spread` apart; a contact is evaluated at either grain's step ends, the other
// predicted there (with a spread of 0 they share a level, and each contact's forces are
// equal and opposite over every shared step).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/integrate/active_share.hpp"
#include "tsubu/integrate/hermite_state.hpp"
#include "tsubu/world/kinematics.hpp"

namespace tsubu {

// The decay rate of a particle's dashpots in their step rule: the block Gershgorin bound
// alone, or the lower of it and the rate measured along the run at each correction
// (docs/integrators.md, "The dashpot rule: a rate measured along the run").
enum class DampingRate : std::uint8_t { bound, measured };

// [simulation.block_steps] of a scenario (docs/scenario.md).
struct BlockStepRules {
  int levels = 20;          // L: steps dt, dt/2, ..., dt/2^L
  int force_level = -1;     // >= 0: every particle on this level (a shared-step Hermite run)
  double kappa_c = 0.04;    // contact step: kappa_c t_coll (Eq. 20) or kappa_c pi sqrt(m*/k)
  double eta_damping = 1.5; // dashpots: lambda h <= eta_damping (BlockHermite::dashpot_step)
  DampingRate damping_rate = DampingRate::bound;  // lambda: the bound, or measured along the run
  double eta_gap = 0.5;     // free particles: share of the time to close a gap
  double eta_tau = 0.1;     // share of the fluid relaxation time
  double eta_a = 0.02;      // Aarseth criterion
  double eta_s = 0.01;      // first step and after a contact begins or ends: eta_s |a|/|j|
  double u_floor = 1e-3;    // m/s, lowest impact speed in Eq. 20
  double list_horizon = 4;  // a moving grain's neighbour list reaches this many dt ahead
  // Grains in touch step on levels at most this many apart: 0, every cluster of touching
  // grains on the finest level any member needs; more, each grain on its own level within
  // that many of its partners' (docs/integrators.md).
  int level_spread = 2;
};

// The coarsest level k whose step dt/2^k is not above `bound` (0 for a bound of dt or more).
// A bound that is zero or NaN (a step rule's value so small that the bound underflowed)
// needs kBeyondLevels, finer than any run's levels: such a grain takes the finest level.
constexpr int kBeyondLevels = 2100;  // above log2 of the ratio of any two positive doubles
int level_needed(double dt, double bound);

// The step rules (docs/integrators.md), as the reason a step got its level: the contacts'
// and gaps' rules of the evaluation, the dashpots', Aarseth's, the fluid's relaxation time,
// the list's reach, a wall's change of motion, the event rule, and the doubling rule (a step
// may double only once, and only where the time is a multiple of the doubled step).
enum class StepRule : std::uint8_t { contact_or_gap, dashpot, aarseth, fluid, list, wall_motion, event, doubling, count };
inline constexpr std::size_t kStepRules = static_cast<std::size_t>(StepRule::count);
inline constexpr const char* kStepRuleNames[kStepRules] = {"contact_or_gap", "dashpot", "aarseth", "fluid",
                                                           "list", "wall_motion", "event", "doubling"};

// What the stepper did, for run.json and the series.
struct BlockStepStats {
  std::uint64_t block_times = 0;
  std::uint64_t wakes = 0;                      // particles woken early by a new contact or a closing gap
  std::vector<std::uint64_t> evaluations;       // particle force evaluations per level
  // The steps chosen after an evaluation (every evaluation but an entering grain's first),
  // by the rule that set their level: the particle's own (set_by_own), or a partner's in
  // touch that raised it, within the level spread or to the cluster's finest level with a
  // spread of 0 (set_by_cluster; by the rule that set that partner's).
  std::vector<std::uint64_t> set_by_own, set_by_cluster;  // kStepRules entries each
};

class BlockHermite {
 public:
  explicit BlockHermite(const BlockStepRules& rules) : rules_(rules) {
    stats_.evaluations.assign(static_cast<std::size_t>(rules.levels) + 1, 0);
    stats_.set_by_own.assign(kStepRules, 0), stats_.set_by_cluster.assign(kStepRules, 0);
  }

  // A fresh run: evaluates every particle at world.step (a multiple of dt) and picks the
  // first steps.
  void start(World& world, ForceField& forces);
  // Continues from a checkpoint: the state as stored; lists rebuilt as they were.
  void resume(World& world, ForceField& forces, HermiteState state, std::vector<Vec3> list_positions,
              std::vector<double> list_reach, bool lists_stale, const BlockStepStats& stats);
  // Particles appended from index `first` between two calls of advance (see
  // Simulation::particles_added): evaluated at the current time, with the lists rebuilt,
  // for their state and first steps.
  void particles_added(World& world, ForceField& forces, std::size_t first);
  // The world's particles were renumbered (sort_spatially, order[new] = old): the Hermite
  // state follows them; the lists are rebuilt at the next block time.
  void renumber(const std::vector<std::uint32_t>& order);
  // At the end of a step, the grains gone through an open face were removed (kept[new] = old
  // for the others): the Hermite state follows, and the lists are rebuilt at once, so that a
  // checkpoint written now holds lists that match the particles.
  void particles_removed(World& world, ForceField& forces, const std::vector<std::uint32_t>& kept);
  // Advances every particle by dt through the block times in between: afterwards all are
  // at time (world.step + 1) dt, which world.step and world.time then say.
  void advance(World& world, ForceField& forces);

  // Block steps shared among processes (docs/parallel.md, "Block steps on several
  // processes"): every process holds every particle and advances alike; at each block time
  // each evaluates and corrects its share of the active particles (a run of the sorted
  // active list), and the processes exchange what they found twice (the evaluation, then the
  // corrected state), so that each ends the block time with one process's bits. `share`
  // must outlive the integrator; null: one process.
  void share_among(ActiveShare* share) { share_ = share; }

  const HermiteState& state() const { return state_; }
  const BlockStepStats& stats() const { return stats_; }
  const std::vector<Vec3>& list_positions() const { return list_positions_; }
  const std::vector<double>& list_reach() const { return list_reach_; }
  bool lists_stale() const { return lists_stale_; }
  // Particles per level now.
  std::vector<std::size_t> level_histogram() const;
  std::uint64_t particle_evaluations() const;

 private:
  BlockStepRules rules_;
  HermiteState state_;
  BlockStepStats stats_;
  EvaluationRates rates_;
  std::vector<std::vector<std::uint32_t>> members_;  // particles of each level
  std::vector<std::uint32_t> slot_;                  // index of each particle in its level's list
  std::vector<char> is_active_;
  std::vector<std::uint32_t> active_;
  std::vector<std::uint32_t> place_in_active_;  // choose_levels' scratch
  // correct_dashpots' scratch: the predicted accelerations of the active particles, and per
  // particle (zero outside the active set) the corrections and the responses to them.
  std::vector<Vec3> predicted_acc_, predicted_alpha_, change_v_, change_w_, change_f_, change_t_;
  std::vector<FluidSlope> fluid_slope_;  // per active particle: the fluid load's slope from the corrector
  std::vector<double> aarseth_;  // per particle, Aarseth's bound from its last correction (infinite where it does not apply)
  std::vector<double> measured_rate_;  // per particle, its dashpots' decay rate along its last correction, 1/s (infinite: unknown)
  std::vector<Kinematics> predicted_;        // predict_around's, per particle
  std::vector<std::int64_t> predicted_at_;   // the block time of each, -1 for none
  std::vector<std::uint32_t> to_predict_;    // predict_around's scratch
  std::vector<Vec3> list_positions_;  // where the lists were built (positions predicted to then)
  std::vector<double> list_reach_;
  bool lists_stale_ = false;
  double list_skin_ = 0;
  ActiveShare* share_ = nullptr;
  std::size_t share_begin_ = 0, share_end_ = 0;  // this process's share of active_ at this block time
  std::vector<char> here_;                       // per particle: in this process's share
  std::string shared_bytes_;                     // what this process sends at this block time
  std::string uncorrected_;                      // its share's state before the corrector

  double tick(const World& world) const;
  // The Predictor of block time `now`, reading the predictions predict_around() made then.
  Predictor predictor_cached(const World& world, std::int64_t now) const;
  // Predicts at t, once each, the active particles from active_[from] on and their listed
  // partners: the evaluation, the waking and the corrector read each many times.
  void predict_around(const World& world, std::int64_t t, std::size_t from);
  void size_scratch(std::size_t n);  // the per-particle scratch arrays for n particles
  std::int64_t step_ticks(int level) const { return std::int64_t{1} << (rules_.levels - level); }
  // The coarsest level whose steps end (and may start) at block time t, ticks.
  int coarsest_on_grid(std::int64_t t) const;
  Predictor predictor(const World& world, std::int64_t now) const;
  // The Hermite state of particle i from its evaluated forces and rates plus the fluid's.
  void take_state(World& world, const ForceField& forces, std::size_t i);
  void set_level(std::uint32_t i, int level);
  void index_levels();
  void collect_active(std::int64_t t);
  void wake(const World& world, std::int64_t t);
  // Process `rank`'s share of the active particles, a run [begin, end) of active_ of equal
  // count, and this process's taken (all of them for one process).
  std::pair<std::size_t, std::size_t> share_of(int rank) const;
  void take_share();
  // The evaluation of the active particles (shared: of this process's share).
  void evaluate(World& world, ForceField& forces, std::int64_t t);
  void correct(World& world, ForceField& forces, std::int64_t t, const std::vector<int>& contacts_before);
  // Shared block steps, once this process has evaluated and corrected its share: every
  // share's evaluation and corrected state on every process, in one exchange. An overlap
  // beyond the limit anywhere ends the step at the evaluation, as for one process: this
  // share's corrections are undone and NumericalError thrown.
  void exchange_share(World& world, ForceField& forces);
  // The values exchange_share sends of each particle of a share: the rates of particle i's
  // evaluation, and what the corrector wrote for active particle q; `each` visits each.
  template <class Each>
  void rates_of(std::uint32_t i, Each&& each);
  template <class Each>
  void corrected(World& world, std::size_t q, Each&& each);
  void correct_dashpots(World& world, const ForceField& forces);
  // The dashpots' step bound of particle i: eta_damping over their decay rate (with
  // `measured`, the lower of the bound and the rate measured at its last correction).
  double dashpot_step(std::uint32_t i, bool measured) const;
  void choose_levels(const World& world, const ForceField& forces, std::int64_t t,
                     const std::vector<int>& contacts_before);
  // choose_levels' end with a level spread: the wishes brought within it of touching partners.
  void spread_levels(const World& world, std::vector<int>& wish, const std::vector<StepRule>& reason);
  void rebuild_lists(World& world, ForceField& forces, std::int64_t t);
  // The lists from list_positions_ and list_reach_, with the walls' places now as theirs.
  void build_lists(World& world, ForceField& forces);
  bool list_outrun(const World& world, const Predictor& kin, std::uint32_t i) const;
  // Moving walls: how far each can travel in the list horizon; their velocities for the
  // steps from block time t (ticks); the time from t to the next change of motion of a wall
  // listed for particle i, s.
  std::vector<double> wall_reach(const World& world) const;
  void walls_at(World& world, std::int64_t t) const;
  double until_wall_event(const World& world, std::uint32_t i, std::int64_t t) const;
  // How far particle i may move from where its list was built before the list misses a
  // neighbour, and how far it has moved when at x.
  double list_limit(std::uint32_t i) const;
  double moved_since_list(const World& world, std::uint32_t i, const Vec3& x) const;
  ContactStepRules contact_rules() const { return {rules_.kappa_c, rules_.eta_gap, rules_.u_floor}; }
  int level_for(double bound, const World& world) const;
};

}  // namespace tsubu
