// The contacts of a run: the neighbour lists (pairs and walls within the skin of touching),
// each entry's contact history, and the index of every particle's entries. The force field
// evaluates and gathers through it, the block-step stepper walks a particle's partners with
// it, and a renumbering of the particles (spatial sort) renumbers it.
//
// A pair's identity and orientation come from the particles' ids, not their indices: its
// first particle is the one with the smaller id, the laws see it from there and its history
// is stored so, and renumbering never changes it. The pair list is sorted by (first
// particle, partner's id), so that a particle's pairs where it is first are one run in its
// partners' id order, and its pairs where it is second (partners with smaller ids) are
// indexed in their partners' id order: a particle visits its pairs by its partners' ids,
// which fixes the gather's summation order whatever the numbering: a run renumbered
// (spatial sort), or split among processes, sums every force in the same order and keeps
// its bits.
#pragma once
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "tsubu/world/particles.hpp"

namespace tsubu {

// Per-contact memory. `xi` is the tangential spring (a vector in the tangent plane); the
// `normal` slots belong to the normal model (each model documents what it keeps there);
// `rolling` is the rolling model's spring torque on i (a vector in the tangent plane).
struct ContactHistory {
  Vec3 xi;
  double normal[2] = {0, 0};
  Vec3 rolling;
};

// Two particle indices (i < j), or a particle and a wall: what a contact search finds.
struct Pair {
  std::uint32_t i, j;
};

// An entry of a neighbour list. Pairs: particles i and j, i the one with the smaller id
// (equal ids, never in a run where ids are unique: the smaller index). Walls: particle i,
// wall j. `touching` says whether it overlapped at the last evaluation; the history of an
// entry that does not is empty.
//
// The contact laws see a pair from its particle i: n points from j to i, and the tangential
// spring xi is the displacement of i's contact point against j's; the history is theirs as
// it is. Had the particles the other order, each history slot would transform so:
//   xi         -> -xi       (a vector in the contact plane, seen from the other side)
//   normal[0]  -> normal[0] (model HH's largest overlap: a property of the pair)
//   normal[1]  -> normal[1] (unused; a new normal slot must be symmetric or listed here)
//   rolling    -> -rolling  (model EPSD's spring torque on i: j feels it negated)
// The pair's geometry gives the same bits, negated, seen from either particle
// (contact_point_velocity), so which particle is first changes no force; the ids only fix
// it for good.
struct Contact {
  std::uint32_t i, j;
  bool touching = false;
  ContactHistory history;
};

// The side an entry is visited from (ContactList::for_each_contact_of): -1 the pair's
// second particle, +1 its first, 0 a wall's particle. A type, so that each of the visit's
// loops has one side, known when it is compiled.
template <int S>
using Side = std::integral_constant<int, S>;

class ContactList {
 public:
  // Pairs sorted by (i, id of j), walls by (i, j).
  std::vector<Contact>& pairs() { return pairs_; }
  const std::vector<Contact>& pairs() const { return pairs_; }
  std::vector<Contact>& walls() { return walls_; }
  const std::vector<Contact>& walls() const { return walls_; }

  // New lists from a search over the particles p (`found` sorted by (i, j); pairs i < j by
  // index, put in the lists' orientation and order here): each entry carries the touching
  // flag and history of the same pair in the old list, or starts empty. Call index() after
  // both.
  void carry_pairs(const std::vector<Pair>& found, const Particles& p);
  void carry_walls(const std::vector<Pair>& found);
  // Lists from elsewhere (a checkpoint, a test; histories stored from the smaller id, in
  // any order and with a pair's particles either way round), indexed over the particles p.
  void assign(std::vector<Contact> pairs, std::vector<Contact> walls, const Particles& p);
  // The particles were renumbered (new_index[old] = new, or kGone for a particle removed;
  // p: the particles, already in their new order): the entries follow their particles and
  // are sorted again, those of a removed particle dropped. No history changes.
  static constexpr std::uint32_t kGone = UINT32_MAX;
  void renumber(const std::vector<std::uint32_t>& new_index, const Particles& p);

  // Where each entry was in the lists before their last change (carry_*, renumber, assign):
  // its index there, or kNew. Stores kept per entry elsewhere (the force field's contact
  // records) follow their entries with follow().
  static constexpr std::uint32_t kNew = UINT32_MAX;
  const std::vector<std::uint32_t>& pair_origin() const { return pair_origin_; }
  const std::vector<std::uint32_t>& wall_origin() const { return wall_origin_; }
  // store[k] = the old store's entry at origin[k], or T{} for an entry new to the lists; an
  // empty store stays empty.
  template <class T>
  static void follow(std::vector<T>& store, const std::vector<std::uint32_t>& origin) {
    if (store.empty()) return;
    std::vector<T> old;
    old.swap(store);
    store.resize(origin.size());
    for (std::size_t k = 0; k < origin.size(); ++k)
      if (origin[k] < old.size()) store[k] = old[origin[k]];
  }

  // The per-particle index over the particles p after the lists changed; release_index()
  // frees it (before a search, to lower the peak memory).
  void index(const Particles& p);
  void release_index() { first_start_ = {}, second_start_ = {}, second_ = {}, wall_start_ = {}; }

  // f(partner, k) for every listed pair k of particle x, in the order of the partners' ids.
  template <class F>
  void for_each_pair_of(std::size_t x, F&& f) const {
    for (std::uint32_t s = second_start_[x]; s < second_start_[x + 1]; ++s) f(pairs_[second_[s]].i, second_[s]);
    for (std::uint32_t k = first_start_[x]; k < first_start_[x + 1]; ++k) f(pairs_[k].j, k);
  }
  // Particle x's wall contacts: the entries [first, last) of walls(), in their partners' order.
  std::pair<std::uint32_t, std::uint32_t> walls_of(std::size_t x) const { return {wall_start_[x], wall_start_[x + 1]}; }
  // f(wall, k) for every listed wall contact k of particle x.
  template <class F>
  void for_each_wall_of(std::size_t x, F&& f) const {
    for (std::uint32_t k = wall_start_[x]; k < wall_start_[x + 1]; ++k) f(walls_[k].j, k);
  }
  // visit(k, side) for particle x's entries in the gather's order: its pairs by their
  // partners' ids, that is first those where x is second (side Side<-1>: the partners with
  // smaller ids) and then those where it is first (Side<+1>: larger ids, a run of the list),
  // then its walls (Side<0>) in the walls' order. Three loops, each of one side.
  template <class Visit>
  [[gnu::always_inline]] void for_each_contact_of(std::size_t x, Visit&& visit) const {
    for (std::uint32_t s = second_start_[x]; s < second_start_[x + 1]; ++s) visit(second_[s], Side<-1>{});
    for (std::uint32_t k = first_start_[x]; k < first_start_[x + 1]; ++k) visit(k, Side<1>{});
    for (std::uint32_t k = wall_start_[x]; k < wall_start_[x + 1]; ++k) visit(k, Side<0>{});
  }

 private:
  std::vector<Contact> pairs_, walls_;
  std::vector<std::uint32_t> pair_origin_, wall_origin_;
  // Particle x's pairs where it is first are pairs_[first_start_[x] .. first_start_[x+1]),
  // already in their partners' id order; those where it is second are the pairs
  // second_[second_start_[x] .. second_start_[x+1]), in their partners' id order. Its walls
  // are walls_[wall_start_[x] .. wall_start_[x+1]).
  std::vector<std::uint32_t> first_start_, second_start_, second_, wall_start_;
};

}  // namespace tsubu
