#include "tsubu/ranks/decomposition.hpp"

#include <algorithm>
#include <cstring>
#include <type_traits>
#include <unordered_map>

namespace tsubu {

namespace {

static_assert(std::is_trivially_copyable_v<ContactLink>);

template <class T>
void put(std::string& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <class T>
T take(const std::string& bytes, std::size_t& at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

// Particle i with everything it carries (every array of Particles).
void pack(const Particles& p, std::size_t i, std::string& out) {
  p.for_each_array([&](const auto& array) { put(out, array[i]); });
}

// Appends `count` particles packed by pack() from bytes[at ...).
void unpack(const std::string& bytes, std::size_t& at, std::size_t count, Particles& p) {
  for (std::size_t k = 0; k < count; ++k)
    p.for_each_array([&](auto& array) { array.push_back(take<typename std::decay_t<decltype(array)>::value_type>(bytes, at)); });
}

// A parcel for one process: particles, then contacts, each preceded by its count.
struct Parcel {
  std::string particles, links;
  std::uint64_t particle_count = 0, link_count = 0;
  std::string bytes() const {
    std::string out;
    put(out, particle_count);
    out += particles;
    put(out, link_count);
    out += links;
    return out;
  }
};

void read_parcel(const std::string& bytes, Particles& particles, std::vector<ContactLink>& links) {
  std::size_t at = 0;
  unpack(bytes, at, take<std::uint64_t>(bytes, at), particles);
  const auto n = take<std::uint64_t>(bytes, at);
  for (std::uint64_t k = 0; k < n; ++k) links.push_back(take<ContactLink>(bytes, at));
}

// The particles' arrays reordered by `order` (order[new] = old).
void reorder(Particles& p, const std::vector<std::size_t>& order) {
  p.for_each_array([&](auto& array) {
    auto old = array;
    for (std::size_t k = 0; k < order.size(); ++k) array[k] = old[order[k]];
  });
}

}  // namespace

Decomposition::Decomposition(const Communicator& comm, const Domain& domain, double skin, double reach,
                             std::array<int, 3> counts)
    : comm_(comm), grid_(domain, comm.size(), counts), skin_(skin), width_(2 * reach + skin) {}

std::vector<ContactLink> Decomposition::links_of(const World& world) {
  const Particles& p = world.particles;
  const std::size_t owned = world.owned();
  std::vector<ContactLink> links;
  for (const Contact& c : world.contacts.pairs())
    if (c.touching && (c.i < owned || c.j < owned))
      links.push_back({std::min(p.id[c.i], p.id[c.j]), std::max(p.id[c.i], p.id[c.j]), -1, c.history});
  for (const Contact& c : world.contacts.walls())
    if (c.touching && c.i < owned) links.push_back({p.id[c.i], 0, static_cast<std::int64_t>(c.j), c.history});
  return links;
}

void Decomposition::distribute(World& world) {
  world.ghosts = 0;
  std::vector<ContactLink> links = links_of(world);  // all of them: this process holds the whole world
  const Particles& p = world.particles;
  std::string bytes;
  std::size_t count = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (grid_.owner(p.position[i]) == comm_.rank()) pack(p, i, bytes), ++count;
  Particles mine;
  std::size_t at = 0;
  unpack(bytes, at, count, mine);
  arrange(world, std::move(mine), std::move(links));
}

void Decomposition::arrange(World& world, Particles owned, std::vector<ContactLink> links) {
  reorder(owned, owned.in_id_order());
  const std::size_t n = owned.size(), processes = static_cast<std::size_t>(comm_.size());
  sent_.assign(processes, {});
  std::vector<std::string> copies(processes);
  std::vector<int> near;
  for (std::size_t i = 0; i < n; ++i) {
    grid_.near(owned.position[i], width_, comm_.rank(), near);
    for (int r : near) {
      sent_[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(i));
      pack(owned, i, copies[static_cast<std::size_t>(r)]);
    }
  }
  const std::vector<std::string> received = comm_.exchange(copies);
  Particles& p = world.particles;
  p = std::move(owned);
  std::size_t bytes_each = 0;
  p.for_each_array([&](const auto& array) { bytes_each += sizeof(typename std::decay_t<decltype(array)>::value_type); });
  received_from_.assign(processes, 0);
  for (std::size_t r = 0; r < processes; ++r) {
    received_from_[r] = p.size();
    std::size_t at = 0;
    unpack(received[r], at, received[r].size() / bytes_each, p);
  }
  world.ghosts = p.size() - n;

  // The contacts of the owned particles, each once, from the ids to this process's indices.
  std::unordered_map<std::int64_t, std::uint32_t> index;
  for (std::uint32_t i = 0; i < p.size(); ++i) index.emplace(p.id[i], i);
  std::sort(links.begin(), links.end(), [](const ContactLink& x, const ContactLink& y) {
    return x.wall != y.wall ? x.wall < y.wall : (x.a != y.a ? x.a < y.a : x.b < y.b);
  });
  links.erase(std::unique(links.begin(), links.end(),
                          [](const ContactLink& x, const ContactLink& y) { return x.wall == y.wall && x.a == y.a && x.b == y.b; }),
              links.end());
  std::vector<Contact> pairs, walls;
  for (const ContactLink& l : links) {
    const auto a = index.find(l.a);
    if (a == index.end()) continue;
    if (l.wall >= 0) {
      if (a->second < n) walls.push_back({a->second, static_cast<std::uint32_t>(l.wall), true, false, l.history});
      continue;
    }
    const auto b = index.find(l.b);
    if (b == index.end() || (a->second >= n && b->second >= n)) continue;
    pairs.push_back({std::min(a->second, b->second), std::max(a->second, b->second), true, false, l.history});
  }
  const auto by_pair = [](const Contact& x, const Contact& y) { return x.i != y.i ? x.i < y.i : x.j < y.j; };
  std::sort(pairs.begin(), pairs.end(), by_pair);
  std::sort(walls.begin(), walls.end(), by_pair);
  world.contacts.assign(std::move(pairs), std::move(walls), p);
  arranged_at_.assign(p.position.begin(), p.position.begin() + static_cast<std::ptrdiff_t>(n));
  ++arrangements_;
}

void Decomposition::refresh_ghosts(World& world) {
  Particles& p = world.particles;
  std::vector<std::string> motion(sent_.size());
  for (std::size_t r = 0; r < sent_.size(); ++r)
    for (std::uint32_t i : sent_[r]) put(motion[r], p.position[i]), put(motion[r], p.velocity[i]), put(motion[r], p.omega[i]);
  const std::vector<std::string> received = comm_.exchange(motion);
  for (std::size_t r = 0; r < received.size(); ++r) {
    std::size_t at = 0, k = received_from_[r];
    for (; at < received[r].size(); ++k) {
      p.position[k] = take<Vec3>(received[r], at);
      p.velocity[k] = take<Vec3>(received[r], at);
      p.omega[k] = take<Vec3>(received[r], at);
    }
  }
}

bool Decomposition::update(World& world) {
  refresh_ghosts(world);
  const Particles& p = world.particles;
  const double limit2 = 0.25 * skin_ * skin_;
  bool moved = false;
  for (std::size_t i = 0; i < world.owned() && !moved; ++i)
    moved = norm2(world.domain.separation(p.position[i], arranged_at_[i])) > limit2;
  if (!comm_.any(moved)) return false;
  // Every owned particle goes to the process of its subdomain (itself, mostly), with the
  // touching contacts of each of its particles: their histories are this process's to give.
  const std::size_t processes = static_cast<std::size_t>(comm_.size());
  std::vector<Parcel> parcels(processes);
  std::vector<int> owner(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) owner[i] = grid_.owner(p.position[i]);
  for (std::size_t i = 0; i < world.owned(); ++i) {
    Parcel& to = parcels[static_cast<std::size_t>(owner[i])];
    pack(p, i, to.particles);
    ++to.particle_count;
  }
  std::unordered_map<std::int64_t, std::size_t> index;
  for (std::size_t i = 0; i < p.size(); ++i) index.emplace(p.id[i], i);
  for (const ContactLink& l : links_of(world)) {
    const auto send = [&](int r) {
      Parcel& to = parcels[static_cast<std::size_t>(r)];
      put(to.links, l);
      ++to.link_count;
    };
    const int first = owner[index.at(l.a)], second = l.wall >= 0 ? first : owner[index.at(l.b)];
    send(first);
    if (second != first) send(second);
  }
  std::vector<std::string> out;
  for (const Parcel& parcel : parcels) out.push_back(parcel.bytes());
  const std::vector<std::string> received = comm_.exchange(out);
  Particles owned;
  std::vector<ContactLink> links;
  for (const std::string& bytes : received) read_parcel(bytes, owned, links);
  arrange(world, std::move(owned), std::move(links));
  return true;
}

World Decomposition::gathered(const World& world) const {
  Parcel mine;
  for (std::size_t i = 0; i < world.owned(); ++i) pack(world.particles, i, mine.particles), ++mine.particle_count;
  for (const ContactLink& l : links_of(world)) put(mine.links, l), ++mine.link_count;
  World all;
  all.domain = world.domain;
  all.walls = world.walls;
  all.dt = world.dt, all.time = world.time, all.step = world.step;
  all.source_ids = world.source_ids;
  const std::vector<std::string> parts = comm_.gather(mine.bytes());
  if (parts.empty()) return all;
  std::vector<ContactLink> links;
  for (const std::string& bytes : parts) read_parcel(bytes, all.particles, links);
  reorder(all.particles, all.particles.in_id_order());
  std::unordered_map<std::int64_t, std::uint32_t> index;
  for (std::uint32_t i = 0; i < all.particles.size(); ++i) index.emplace(all.particles.id[i], i);
  std::vector<Contact> pairs, walls;
  for (const ContactLink& l : links) {
    if (l.wall >= 0) walls.push_back({index.at(l.a), static_cast<std::uint32_t>(l.wall), true, false, l.history});
    else pairs.push_back({index.at(l.a), index.at(l.b), true, false, l.history});
  }
  const auto by_pair = [](const Contact& x, const Contact& y) { return x.i != y.i ? x.i < y.i : x.j < y.j; };
  const auto same = [](const Contact& x, const Contact& y) { return x.i == y.i && x.j == y.j; };
  std::sort(pairs.begin(), pairs.end(), by_pair);
  pairs.erase(std::unique(pairs.begin(), pairs.end(), same), pairs.end());
  std::sort(walls.begin(), walls.end(), by_pair);
  all.contacts.assign(std::move(pairs), std::move(walls), all.particles);
  return all;
}

}  // namespace tsubu
