// A run split among processes by a Cartesian grid of subdomains (docs/parallel.md). Each
// process holds the particles in its subdomain (owned, first in world.particles, in the
// order of their ids) and copies of the other processes' particles within reach of it
// (ghosts, last: World::ghosts), with the touching contacts of its owned particles. Before
// every evaluation (ForceField's Neighbourhood) it refreshes the ghosts' motion; once a
// particle has moved half the skin since the last arrangement, the processes hand the
// particles that left their subdomains, with their contact histories, to their new owners
// and build the ghost sets again.
//
// The same bits for any number of processes: a process evaluates every contact of its
// owned particles, with a ghost partner exactly as the partner's process evaluates it (a
// pair seen from either particle gives the same bits negated, the contact history is
// stored by id), sums each particle's contacts in its partners' id order, and integrates
// only its owned particles; no result depends on when the lists are built.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/ranks/communicator.hpp"
#include "tsubu/ranks/rank_grid.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

// A touching contact by its particles' ids: a pair (a < b, the history as seen from a), or
// particle a on wall `wall`.
struct ContactLink {
  std::int64_t a = 0, b = 0;
  std::int64_t wall = -1;  // -1 for a pair
  ContactHistory history;
};

// What a process of a split run holds and has sent: its owned particles, its copies of
// others' (ghosts) and the pairs of its neighbour list, now; the bytes it has sent to other
// processes in its exchanges of particles (ghost copies and motion, hand-overs) and how
// often the particles were arranged, since the run (or its resume) began.
struct ProcessLoad {
  std::uint64_t owned = 0, ghosts = 0, listed_pairs = 0, bytes_sent = 0, arrangements = 0;
};

class Decomposition final : public Neighbourhood {
 public:
  // `skin`: the margin of the hand-overs (the same on every process; a particle is handed
  // over once it has moved half of it); two particles act on each other up to
  // `reach_per_radius` times the largest radius apart (ForceField::reach_per_radius), the
  // largest radius being `largest_radius` or that of a larger grain added since (add).
  // `counts`: the grid of subdomains (RankGrid), automatic when zero. `balance`: the cuts
  // follow the work at every arrangement (each slab between two cuts of an axis holds an
  // equal share of it: a particle's work is one plus the pairs of its list), or stay evenly
  // spaced.
  Decomposition(const Communicator& comm, const Domain& domain, double skin, double reach_per_radius,
                double largest_radius, std::array<int, 3> counts = {0, 0, 0}, bool balance = true);

  const RankGrid& grid() const { return grid_; }
  // How often the particles were arranged among the processes (distribute included).
  std::size_t arrangements() const { return arrangements_; }
  // Keeps this process's part of a world that every process holds whole (built from the
  // scenario or read from a checkpoint), with its ghosts.
  void distribute(World& world);
  // Neighbourhood: before each evaluation.
  bool update(World& world, bool lost) override;
  void agree_any(std::vector<char>& flags) const override;
  void add(World& world, Particles arrivals, const ForceField& forces) override;
  void remove(World& world, const std::vector<std::int64_t>& ids) override;
  std::vector<std::string> gather_all(const std::string& bytes) override;
  // The owned particles and their touching contacts of every process, on process 0, as one
  // world: particles in the order of their ids, contacts as a checkpoint stores them, with
  // the results of their last evaluation (`forces`'s) for the world's lists, which a force
  // field adopts (ForceField::adopt_results) for the outputs of one process. Other processes
  // get an empty world. For outputs and tests.
  struct Gathered {
    World world;
    std::vector<ContactResult> pair_results, wall_results;
    std::vector<ProcessLoad> loads;  // by process
  };
  Gathered gathered(const World& world, const ForceField& forces) const;

 private:
  const Communicator& comm_;
  RankGrid grid_;
  double skin_, reach_per_radius_, largest_radius_;
  double width_;  // the ghost layer's: reach_per_radius_ largest_radius_ + skin_
  std::vector<Vec3> arranged_at_;  // the owned particles' positions at the last arrangement
  std::vector<std::vector<std::uint32_t>> sent_;  // per process, the owned particles it has copies of
  std::vector<std::size_t> received_from_;        // per process, where its copies begin in world.particles
  std::vector<std::size_t> ghosts_from_;          // per process, how many copies of its particles this one has
  std::size_t arrangements_ = 0;
  std::uint64_t bytes_sent_ = 0;  // to other processes, in exchange()
  bool rearranged_ = false;  // particles were added or removed since the last update
  // The touching contacts of the owned particles with their results (records as gathered()
  // sends them), as the last evaluation left them, when particles were added after it: the
  // arrangement renumbers the lists, so the results are gathered from here until the next
  // update.
  std::string evaluated_links_;
  std::uint64_t evaluated_link_count_ = 0;
  bool links_kept_ = false;
  bool balance_;

  // Settles `owned` (this process's particles, any order) and `links` (touching contacts of
  // them, possibly repeated) as the world's particles and lists, with new ghosts.
  void arrange(World& world, Particles owned, std::vector<ContactLink> links);
  // comm_.exchange, counting the bytes sent to other processes.
  std::vector<std::string> exchange(const std::vector<std::string>& to_each, const std::vector<std::size_t>* sizes = nullptr);
  // Brings the ghosts' motion from their owners, and with it each process's `flags` (bits):
  // the "or" of every process's.
  char refresh_ghosts(World& world, char flags);
  // Moves the grid's cuts to the work of the world's particles: of all of them when every
  // process holds the whole world (`whole`), else of every process's owned particles.
  void rebalance(const World& world, bool whole);
  // Hands every owned particle, with its touching contacts, to the process of its subdomain,
  // and this process's `arrivals` to itself; then arranges.
  void hand_over(World& world, const Particles& arrivals);
};

}  // namespace tsubu
