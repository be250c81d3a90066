#include "tsubu/world/contact_list.hpp"

#include <algorithm>
#include <numeric>

namespace tsubu {

namespace {

bool by_pair(const Contact& a, const Contact& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }

// start[i] = how many contacts have particle(c) < i, for i = 0..n (for a list sorted by
// particle(c), the first of particle i's contacts).
template <class Particle>
void count_starts(const std::vector<Contact>& contacts, std::size_t n, Particle particle, std::vector<std::uint32_t>& start) {
  start.assign(n + 1, 0);
  for (const Contact& c : contacts) ++start[particle(c) + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
}

}  // namespace

// Both lists sorted by (i, j): one merge pass.
std::vector<Contact> ContactList::carry(const std::vector<Pair>& found, const std::vector<Contact>& old,
                                       std::vector<std::uint32_t>& origin) {
  std::vector<Contact> out(found.size());
  origin.assign(found.size(), kNew);
  std::size_t o = 0;
  for (std::size_t k = 0; k < found.size(); ++k) {
    const Pair& f = found[k];
    while (o < old.size() && (old[o].i < f.i || (old[o].i == f.i && old[o].j < f.j))) ++o;
    out[k].i = f.i;
    out[k].j = f.j;
    if (o < old.size() && old[o].i == f.i && old[o].j == f.j) {
      out[k].touching = old[o].touching;  // as of the last evaluation
      out[k].history = old[o].history;
      origin[k] = static_cast<std::uint32_t>(o);
    }
  }
  return out;
}

void ContactList::assign(std::vector<Contact> pairs, std::vector<Contact> walls, const Particles& p) {
  pairs_ = std::move(pairs);
  walls_ = std::move(walls);
  pair_origin_.assign(pairs_.size(), kNew);
  wall_origin_.assign(walls_.size(), kNew);
  index(p);
}

void ContactList::renumber(const std::vector<std::uint32_t>& new_index, const Particles& p) {
  for (Contact& c : pairs_) {
    c.i = new_index[c.i], c.j = new_index[c.j];
    if (c.i > c.j) std::swap(c.i, c.j);  // the history, stored by id, stays as it is
  }
  for (Contact& c : walls_) c.i = new_index[c.i];
  sort_by_pair(pairs_, pair_origin_);
  sort_by_pair(walls_, wall_origin_);
  index(p);
}

void ContactList::sort_by_pair(std::vector<Contact>& list, std::vector<std::uint32_t>& origin) {
  origin.resize(list.size());
  std::iota(origin.begin(), origin.end(), 0u);
  std::sort(origin.begin(), origin.end(), [&](std::uint32_t a, std::uint32_t b) { return by_pair(list[a], list[b]); });
  std::vector<Contact> sorted(list.size());
  for (std::size_t k = 0; k < list.size(); ++k) sorted[k] = list[origin[k]];
  list = std::move(sorted);
}

void ContactList::index(const Particles& p) {
  const std::size_t n = p.size();
  for (Contact& c : pairs_) c.turned = p.id[c.i] > p.id[c.j];
  incident_start_.assign(n + 1, 0);
  for (const Contact& c : pairs_) ++incident_start_[c.i + 1], ++incident_start_[c.j + 1];
  for (std::size_t i = 0; i < n; ++i) incident_start_[i + 1] += incident_start_[i];
  incident_.resize(2 * pairs_.size());
  std::vector<std::uint32_t> fill(incident_start_.begin(), incident_start_.end() - 1);
  for (std::uint32_t k = 0; k < pairs_.size(); ++k) {
    incident_[fill[pairs_[k].i]++] = 2 * k;
    incident_[fill[pairs_[k].j]++] = 2 * k + 1;
  }
  // Each particle's pairs by their partners' ids: the gather's summation order (ids are unique).
  for (std::size_t i = 0; i < n; ++i)
    std::sort(incident_.begin() + incident_start_[i], incident_.begin() + incident_start_[i + 1],
              [&](std::uint32_t a, std::uint32_t b) { return p.id[partner(a)] < p.id[partner(b)]; });
  count_starts(walls_, n, [](const Contact& c) { return c.i; }, wall_start_);
}

}  // namespace tsubu
