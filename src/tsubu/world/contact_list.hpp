// The contacts of a run: the neighbour lists (pairs and walls within the skin of touching),
// each entry's contact history, and the index of every particle's entries. The force field
// evaluates and gathers through it, the block-step stepper walks a particle's partners with
// it, and a renumbering of the particles (spatial sort) renumbers it.
//
// A pair's identity and orientation come from the particles' ids, not their indices: its
// history is stored as seen from the particle with the smaller id, so renumbering never
// changes it. The lists are ordered by index; a particle's pairs are visited in the order of
// their partners' ids, which fixes the gather's summation order whatever the numbering: a
// run renumbered (spatial sort), or split among processes, sums every force in the same
// order and keeps its bits.
#pragma once
#include <bit>
#include <cstdint>
#include <vector>

#include "tsubu/world/particles.hpp"

namespace tsubu {

// Per-contact memory. `xi` is the tangential spring (a vector in the tangent plane); the
// `normal` slots belong to the normal model (each model documents what it keeps there).
struct ContactHistory {
  Vec3 xi;
  double normal[2] = {0, 0};
};

// Two particle indices (i < j), or a particle and a wall: what a contact search finds.
struct Pair {
  std::uint32_t i, j;
};

// An entry of a neighbour list. Pairs: particles i < j (indices). Walls: particle i, wall j.
// `touching` says whether it overlapped at the last evaluation; the history of an entry
// that does not is empty.
//
// A pair's history is stored as seen from its particle with the smaller id. The contact
// laws see a pair from its particle i: n points from j to i, and the tangential spring xi is
// the displacement of i's contact point against j's. When the two particles swap roles each
// history slot transforms as follows (law_history() and set_law_history() apply it when the
// smaller id is j's):
//   xi         -> -xi       (a vector in the contact plane, seen from the other side)
//   normal[0]  -> normal[0] (model HH's largest overlap: a property of the pair)
//   normal[1]  -> normal[1] (unused; a new normal slot must be symmetric or listed here)
// Negation is exact, so the laws get the same bits as if the spring were stored from i (but
// for the sign of the zeros of an empty spring, which no particle's force sees: its sums
// start from +0, and +0 plus or minus a zero is +0). Equal ids (never in a run, where ids
// are unique) keep the index order.
struct Contact {
  std::uint32_t i, j;
  bool touching = false;
  // Pairs only: the smaller id is j's, so the laws' history is the stored one turned. Set
  // by ContactList::index() from the particles' ids (kept with the entry, so that the
  // evaluation reads no id and takes no branch on it).
  bool turned = false;
  ContactHistory history;

  // Pairs only. The turn flips the spring's sign bits, without a branch (whether a pair is
  // turned is unpredictable once the particles are sorted in space).
  ContactHistory law_history() const {
    ContactHistory h = history;
    h.xi = turn(h.xi);
    return h;
  }
  void set_law_history(ContactHistory h) {
    h.xi = turn(h.xi);
    history = h;
  }

 private:
  Vec3 turn(const Vec3& v) const {
    const std::uint64_t sign = std::uint64_t{turned} << 63;
    const auto flip = [&](double x) { return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) ^ sign); };
    return {flip(v.x), flip(v.y), flip(v.z)};
  }
};

class ContactList {
 public:
  // Sorted by (i, j).
  std::vector<Contact>& pairs() { return pairs_; }
  const std::vector<Contact>& pairs() const { return pairs_; }
  std::vector<Contact>& walls() { return walls_; }
  const std::vector<Contact>& walls() const { return walls_; }

  // New lists from a search (`found` sorted by (i, j)): each entry carries the touching flag
  // and history of the same pair in the old list, or starts empty. Call index() after both.
  void carry_pairs(const std::vector<Pair>& found) { pairs_ = carry(found, pairs_, pair_origin_); }
  void carry_walls(const std::vector<Pair>& found) { walls_ = carry(found, walls_, wall_origin_); }
  // Lists from elsewhere (a checkpoint, a test; histories stored by id, sorted by (i, j)),
  // indexed over the particles p.
  void assign(std::vector<Contact> pairs, std::vector<Contact> walls, const Particles& p);
  // The particles were renumbered (new_index[old] = new; p: the particles, already in their
  // new order): the entries follow their particles and are sorted by (i, j) again. No
  // history changes.
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

  // The per-particle index over the particles p, and each pair's turn (Contact::turned),
  // after the lists changed; release_index() frees the index (before a search, to lower the
  // peak memory).
  void index(const Particles& p);
  void release_index() { incident_start_ = {}, incident_ = {}, wall_start_ = {}; }

  // f(partner, k) for every listed pair k of particle i.
  template <class F>
  void for_each_pair_of(std::size_t i, F&& f) const {
    for (std::uint32_t s = incident_start_[i]; s < incident_start_[i + 1]; ++s) f(partner(incident_[s]), incident_[s] >> 1);
  }
  // f(wall, k) for every listed wall contact k of particle i.
  template <class F>
  void for_each_wall_of(std::size_t i, F&& f) const {
    for (std::uint32_t k = wall_start_[i]; k < wall_start_[i + 1]; ++k) f(walls_[k].j, k);
  }
  // visit(k, side) for particle i's entries in the gather's order: its pairs by their
  // partners' ids (side -1 where i is the pair's second, +1 where it is the first), then its
  // walls (side 0) in the walls' order.
  template <class Visit>
  [[gnu::always_inline]] void for_each_contact_of(std::size_t i, Visit&& visit) const {
    for (std::uint32_t s = incident_start_[i]; s < incident_start_[i + 1]; ++s)
      visit(incident_[s] >> 1, (incident_[s] & 1) ? -1 : 1);
    for (std::uint32_t k = wall_start_[i]; k < wall_start_[i + 1]; ++k) visit(k, 0);
  }

 private:
  std::vector<Contact> pairs_, walls_;
  std::vector<std::uint32_t> pair_origin_, wall_origin_;
  // Particle i's pairs are incident_[incident_start_[i] .. incident_start_[i+1]), each 2k + 1
  // where i is pair k's second and 2k where it is its first, in the order of the partners'
  // ids. The walls are sorted by (i, j): particle i's are [wall_start_[i], wall_start_[i+1]).
  std::vector<std::uint32_t> incident_start_, incident_, wall_start_;
  // The other particle of an incident_ entry.
  std::uint32_t partner(std::uint32_t e) const { return (e & 1) ? pairs_[e >> 1].i : pairs_[e >> 1].j; }

  static std::vector<Contact> carry(const std::vector<Pair>& found, const std::vector<Contact>& old,
                                    std::vector<std::uint32_t>& origin);
  // The entries sorted by (i, j) again after their indices changed, with their origins.
  static void sort_by_pair(std::vector<Contact>& list, std::vector<std::uint32_t>& origin);
};

}  // namespace tsubu
