#include "tsubu/world/contact_list.hpp"

#include <algorithm>
#include <utility>

namespace tsubu {

namespace {

// Whether particle a comes before particle b in the order of their ids (equal ids, never in
// a run: of their indices).
bool before(const Particles& p, std::uint32_t a, std::uint32_t b) { return p.id[a] != p.id[b] ? p.id[a] < p.id[b] : a < b; }

// A pair (Pair or Contact) in the lists' orientation: its first particle the one with the
// smaller id. The history, stored so, stays as it is.
template <class Entry>
void orient(Entry& e, const Particles& p) {
  if (before(p, e.j, e.i)) std::swap(e.i, e.j);
}

// The pair list's order: by first particle, then by the partner's id.
struct PairOrder {
  const Particles& p;
  bool operator()(const Contact& a, const Contact& b) const { return a.i != b.i ? a.i < b.i : before(p, a.j, b.j); }
};
// The wall list's order: by particle, then by wall.
struct WallOrder {
  bool operator()(const Contact& a, const Contact& b) const { return a.i != b.i ? a.i < b.i : a.j < b.j; }
};

// start[x] = how many entries have particle(e) < x, for x = 0..n (for a list sorted by
// particle(e), the first of particle x's entries).
template <class Entry, class Particle>
void count_starts(const std::vector<Entry>& entries, std::size_t n, Particle particle, std::vector<std::uint32_t>& start) {
  start.assign(n + 1, 0);
  for (const Entry& e : entries) ++start[particle(e) + 1];
  for (std::size_t x = 0; x < n; ++x) start[x + 1] += start[x];
}

// The order of oriented pairs in the pair list: order[m] = the pair that comes m-th. A
// counting sort by first particle, then each particle's run (a few pairs) by its partners'
// ids.
std::vector<std::uint32_t> pair_order(const std::vector<Pair>& pairs, const Particles& p) {
  std::vector<std::uint32_t> start;
  count_starts(pairs, p.size(), [](const Pair& e) { return e.i; }, start);
  std::vector<std::uint32_t> order(pairs.size()), fill(start.begin(), start.end() - 1);
  for (std::uint32_t k = 0; k < pairs.size(); ++k) order[fill[pairs[k].i]++] = k;
  for (std::size_t x = 0; x < p.size(); ++x)
    std::sort(order.begin() + start[x], order.begin() + start[x + 1],
              [&](std::uint32_t a, std::uint32_t b) { return before(p, pairs[a].j, pairs[b].j); });
  return order;
}

// `out` (in the list's order) with the touching flag and history of each entry that `old`
// (in the same order) holds: one merge pass. origin[k]: out[k]'s index in old, or kNew.
template <class Order>
std::vector<Contact> carry(std::vector<Contact> out, const std::vector<Contact>& old, std::vector<std::uint32_t>& origin,
                           Order less) {
  origin.assign(out.size(), ContactList::kNew);
  std::size_t o = 0;
  for (std::size_t k = 0; k < out.size(); ++k) {
    while (o < old.size() && less(old[o], out[k])) ++o;
    if (o < old.size() && old[o].i == out[k].i && old[o].j == out[k].j) {
      out[k].touching = old[o].touching;  // as of the last evaluation
      out[k].history = old[o].history;
      origin[k] = static_cast<std::uint32_t>(o);
    }
  }
  return out;
}

// The walls sorted by (i, j) again, with origin[k] = the index the k-th had.
void sort_walls(std::vector<Contact>& walls, std::vector<std::uint32_t>& origin) {
  origin.resize(walls.size());
  for (std::uint32_t k = 0; k < walls.size(); ++k) origin[k] = k;
  std::sort(origin.begin(), origin.end(), [&](std::uint32_t a, std::uint32_t b) { return WallOrder{}(walls[a], walls[b]); });
  std::vector<Contact> sorted(walls.size());
  for (std::size_t k = 0; k < walls.size(); ++k) sorted[k] = walls[origin[k]];
  walls = std::move(sorted);
}

// The pairs oriented and in the list's order, with origin[m] = the index the m-th had.
void sort_pairs(std::vector<Contact>& pairs, std::vector<std::uint32_t>& origin, const Particles& p) {
  std::vector<Pair> oriented(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) orient(pairs[k], p), oriented[k] = {pairs[k].i, pairs[k].j};
  origin = pair_order(oriented, p);
  std::vector<Contact> sorted(pairs.size());
  for (std::size_t m = 0; m < pairs.size(); ++m) sorted[m] = pairs[origin[m]];
  pairs = std::move(sorted);
}

}  // namespace

// The search's pairs (i < j by index, sorted by (i, j)) are oriented by ids and put in the
// list's order; the old list is in that order too (ids and indices are the same between
// renumberings).
void ContactList::carry_pairs(const std::vector<Pair>& found, const Particles& p) {
  std::vector<Pair> oriented(found);
  for (Pair& e : oriented) orient(e, p);
  const std::vector<std::uint32_t> order = pair_order(oriented, p);
  std::vector<Contact> out(found.size());
  for (std::size_t m = 0; m < out.size(); ++m) out[m].i = oriented[order[m]].i, out[m].j = oriented[order[m]].j;
  pairs_ = carry(std::move(out), pairs_, pair_origin_, PairOrder{p});
}

void ContactList::carry_walls(const std::vector<Pair>& found) {
  std::vector<Contact> out(found.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k].i = found[k].i, out[k].j = found[k].j;
  walls_ = carry(std::move(out), walls_, wall_origin_, WallOrder{});  // found: sorted by (i, j)
}

void ContactList::assign(std::vector<Contact> pairs, std::vector<Contact> walls, const Particles& p) {
  pairs_ = std::move(pairs);
  walls_ = std::move(walls);
  sort_pairs(pairs_, pair_origin_, p);
  sort_walls(walls_, wall_origin_);
  pair_origin_.assign(pairs_.size(), kNew);
  wall_origin_.assign(walls_.size(), kNew);
  index(p);
}

namespace {

// The entries of `list` whose particles stay, renumbered (new_index as ContactList::renumber
// takes it; pairs: both particles); returns kept[m] = the index the m-th had.
std::vector<std::uint32_t> keep_renumbered(std::vector<Contact>& list, const std::vector<std::uint32_t>& new_index,
                                           bool pairs) {
  std::vector<std::uint32_t> kept;
  kept.reserve(list.size());
  std::size_t m = 0;
  for (std::uint32_t k = 0; k < list.size(); ++k) {
    Contact c = list[k];
    c.i = new_index[c.i];
    if (pairs) c.j = new_index[c.j];  // still the smaller id first
    if (c.i == ContactList::kGone || (pairs && c.j == ContactList::kGone)) continue;
    list[m++] = c;
    kept.push_back(k);
  }
  list.resize(m);
  return kept;
}

}  // namespace

void ContactList::renumber(const std::vector<std::uint32_t>& new_index, const Particles& p) {
  const std::vector<std::uint32_t> kept_pairs = keep_renumbered(pairs_, new_index, true);
  const std::vector<std::uint32_t> kept_walls = keep_renumbered(walls_, new_index, false);
  sort_pairs(pairs_, pair_origin_, p);
  sort_walls(walls_, wall_origin_);
  for (std::uint32_t& o : pair_origin_) o = kept_pairs[o];
  for (std::uint32_t& o : wall_origin_) o = kept_walls[o];
  index(p);
}

void ContactList::index(const Particles& p) {
  const std::size_t n = p.size();
  count_starts(pairs_, n, [](const Contact& c) { return c.i; }, first_start_);
  count_starts(pairs_, n, [](const Contact& c) { return c.j; }, second_start_);
  second_.resize(pairs_.size());
  std::vector<std::uint32_t> fill(second_start_.begin(), second_start_.end() - 1);
  for (std::uint32_t k = 0; k < pairs_.size(); ++k) second_[fill[pairs_[k].j]++] = k;
  // Each particle's pairs where it is second by their partners' ids: the gather's order.
  for (std::size_t x = 0; x < n; ++x)
    std::sort(second_.begin() + second_start_[x], second_.begin() + second_start_[x + 1],
              [&](std::uint32_t a, std::uint32_t b) { return before(p, pairs_[a].i, pairs_[b].i); });
  count_starts(walls_, n, [](const Contact& c) { return c.i; }, wall_start_);
}

}  // namespace tsubu
