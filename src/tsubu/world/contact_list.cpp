#include "tsubu/world/contact_list.hpp"

#include <algorithm>

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
std::vector<Contact> ContactList::carry(const std::vector<Pair>& found, const std::vector<Contact>& old) {
  std::vector<Contact> out(found.size());
  std::size_t o = 0;
  for (std::size_t k = 0; k < found.size(); ++k) {
    const Pair& f = found[k];
    while (o < old.size() && (old[o].i < f.i || (old[o].i == f.i && old[o].j < f.j))) ++o;
    out[k].i = f.i;
    out[k].j = f.j;
    if (o < old.size() && old[o].i == f.i && old[o].j == f.j) {
      out[k].touching = old[o].touching;  // as of the last evaluation
      out[k].history = old[o].history;
    }
  }
  return out;
}

void ContactList::assign(std::vector<Contact> pairs, std::vector<Contact> walls, const Particles& p) {
  pairs_ = std::move(pairs);
  walls_ = std::move(walls);
  index(p);
}

void ContactList::renumber(const std::vector<std::uint32_t>& new_index, const Particles& p) {
  for (Contact& c : pairs_) {
    c.i = new_index[c.i], c.j = new_index[c.j];
    if (c.i > c.j) std::swap(c.i, c.j);  // the history, stored by id, stays as it is
  }
  for (Contact& c : walls_) c.i = new_index[c.i];
  std::sort(pairs_.begin(), pairs_.end(), by_pair);
  std::sort(walls_.begin(), walls_.end(), by_pair);
  index(p);
}

void ContactList::index(const Particles& p) {
  const std::size_t n = p.size();
  for (Contact& c : pairs_) c.turned = p.id[c.i] > p.id[c.j];
  auto first = [](const Contact& c) { return c.i; };
  count_starts(pairs_, n, first, first_start_);
  count_starts(pairs_, n, [](const Contact& c) { return c.j; }, second_start_);
  second_index_.resize(pairs_.size());
  std::vector<std::uint32_t> fill(second_start_.begin(), second_start_.end() - 1);
  for (std::uint32_t k = 0; k < pairs_.size(); ++k) second_index_[fill[pairs_[k].j]++] = k;
  count_starts(walls_, n, first, wall_start_);
}

}  // namespace tsubu
