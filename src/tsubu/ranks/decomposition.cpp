#include "tsubu/ranks/decomposition.hpp"

#include <algorithm>
#include <cstring>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "tsubu/core/bytes.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/world/spatial_sort.hpp"

namespace tsubu {

namespace {

static_assert(std::is_trivially_copyable_v<ContactLink> && std::is_trivially_copyable_v<ContactResult>);

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

// Reads a parcel's particles into `particles` and calls read_link(bytes, at) once per
// contact, at the position of its record.
template <class ReadLink>
void read_parcel(const std::string& bytes, Particles& particles, ReadLink read_link) {
  std::size_t at = 0;
  unpack(bytes, at, take<std::uint64_t>(bytes, at), particles);
  for (auto n = take<std::uint64_t>(bytes, at); n > 0; --n) read_link(bytes, at);
}

// The order of the contact lists once the particles are in id order: pairs by (first id,
// second id), then walls by (particle's id, wall). Equal keys are the same contact.
auto link_key(const ContactLink& l) { return std::tuple(l.wall >= 0, l.a, l.wall >= 0 ? l.wall : l.b); }

// The particles in id order.
void in_id_order(Particles& p) {
  const std::vector<std::size_t> order = p.in_id_order();
  p.for_each_array([&](auto& array) { permute(array, order); });
}

// The contacts of `links` (by ids; histories as seen from the smaller id) as the lists over
// the particles p, the first `owned` of them this process's: each contact once, and only
// those this process evaluates: a wall's with an owned particle, a pair's with at least one.
void assign_contacts(ContactList& contacts, std::vector<ContactLink> links, const Particles& p, std::size_t owned) {
  std::sort(links.begin(), links.end(), [](const ContactLink& x, const ContactLink& y) { return link_key(x) < link_key(y); });
  links.erase(std::unique(links.begin(), links.end(),
                          [](const ContactLink& x, const ContactLink& y) { return link_key(x) == link_key(y); }),
              links.end());
  std::unordered_map<std::int64_t, std::uint32_t> index;
  for (std::uint32_t i = 0; i < p.size(); ++i) index.emplace(p.id[i], i);
  std::vector<Contact> pairs, walls;
  for (const ContactLink& l : links) {
    const auto a = index.find(l.a);
    if (a == index.end()) continue;
    if (l.wall >= 0) {
      if (a->second < owned) walls.push_back({a->second, static_cast<std::uint32_t>(l.wall), true, l.history});
      continue;
    }
    const auto b = index.find(l.b);
    if (b != index.end() && (a->second < owned || b->second < owned))
      pairs.push_back({a->second, b->second, true, l.history});
  }
  contacts.assign(std::move(pairs), std::move(walls), p);  // sorts them into the lists' order
}

// Calls visit(link, wall, k) for each touching contact of the owned particles: entry k of
// the pair list (wall false) or of the wall list.
template <class Visit>
void for_each_link(const World& world, Visit visit) {
  const std::vector<std::int64_t>& id = world.particles.id;
  const std::size_t owned = world.owned();
  const std::vector<Contact>& pairs = world.contacts.pairs();
  const std::vector<Contact>& walls = world.contacts.walls();
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (const Contact& c = pairs[k]; c.touching && (c.i < owned || c.j < owned))
      visit(ContactLink{id[c.i], id[c.j], -1, c.history}, false, k);  // i: the smaller id
  for (std::size_t k = 0; k < walls.size(); ++k)
    if (const Contact& c = walls[k]; c.touching && c.i < owned)
      visit(ContactLink{id[c.i], 0, static_cast<std::int64_t>(c.j), c.history}, true, k);
}

// The touching contacts of the owned particles.
std::vector<ContactLink> links_of(const World& world) {
  std::vector<ContactLink> links;
  for_each_link(world, [&](const ContactLink& l, bool, std::size_t) { links.push_back(l); });
  return links;
}

// Each touching contact of the owned particles with its result of `forces`'s last
// evaluation (a ContactLink, then a ContactResult); `count` is set to their number.
std::string link_records(const World& world, const ForceField& forces, std::uint64_t& count) {
  std::string out;
  count = 0;
  for_each_link(world, [&](const ContactLink& l, bool wall, std::size_t k) {
    put(out, l), put(out, wall ? forces.wall_result(k) : forces.pair_result(k)), ++count;
  });
  return out;
}

}  // namespace

Decomposition::Decomposition(const Communicator& comm, const Domain& domain, double skin, double reach_per_radius,
                             double largest_radius, std::array<int, 3> counts, bool balance)
    : comm_(comm),
      grid_(domain, comm.size(), counts),
      skin_(skin),
      reach_per_radius_(reach_per_radius),
      largest_radius_(largest_radius),
      width_(reach_per_radius * largest_radius + skin),
      balance_(balance) {}

void Decomposition::rebalance(const World& world, bool whole) {
  if (!balance_ || comm_.size() == 1) return;
  const Particles& p = world.particles;
  const std::size_t owned = world.owned();
  std::vector<std::int64_t> work(owned, 1);
  for (const Contact& c : world.contacts.pairs()) {
    if (c.i < owned) ++work[c.i];
    if (c.j < owned) ++work[c.j];
  }
  std::vector<std::int64_t> bins;  // the bins of the three axes, one after another
  for (int a = 0; a < 3; ++a) {
    const std::size_t first = bins.size();
    bins.resize(first + static_cast<std::size_t>(grid_.bins(a)), 0);
    for (std::size_t i = 0; i < owned; ++i) bins[first + static_cast<std::size_t>(grid_.bin(a, p.position[i][a]))] += work[i];
  }
  if (!whole) bins = comm_.sum(std::move(bins));
  std::array<std::vector<std::int64_t>, 3> per_axis;
  auto first = bins.begin();
  for (int a = 0; a < 3; ++a) {
    const auto last = first + grid_.bins(a);
    per_axis[static_cast<std::size_t>(a)].assign(first, last);
    first = last;
  }
  grid_.balance(per_axis);
}

void Decomposition::distribute(World& world) {
  world.ghosts = 0;
  rebalance(world, true);
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
  in_id_order(owned);
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
  const std::vector<std::string> received = exchange(copies);
  Particles& p = world.particles;
  p = std::move(owned);
  std::size_t bytes_each = 0;
  p.for_each_array([&](const auto& array) { bytes_each += sizeof(typename std::decay_t<decltype(array)>::value_type); });
  received_from_.assign(processes, 0);
  ghosts_from_.assign(processes, 0);
  for (std::size_t r = 0; r < processes; ++r) {
    received_from_[r] = p.size();
    ghosts_from_[r] = received[r].size() / bytes_each;
    std::size_t at = 0;
    unpack(received[r], at, ghosts_from_[r], p);
  }
  world.ghosts = p.size() - n;

  assign_contacts(world.contacts, std::move(links), p, n);
  arranged_at_.assign(p.position.begin(), p.position.begin() + static_cast<std::ptrdiff_t>(n));
  ++arrangements_;
}

std::vector<std::string> Decomposition::exchange(const std::vector<std::string>& to_each,
                                                 const std::vector<std::size_t>* sizes) {
  for (std::size_t r = 0; r < to_each.size(); ++r)
    if (static_cast<int>(r) != comm_.rank()) bytes_sent_ += to_each[r].size();
  return sizes ? comm_.exchange(to_each, *sizes) : comm_.exchange(to_each);
}

char Decomposition::refresh_ghosts(World& world, char flags) {
  Particles& p = world.particles;
  // To every process (all of them, so that each hears every flag): the flags, then the motion
  // of the particles it has copies of, whose number it knows.
  constexpr std::size_t kMotion = 3 * sizeof(Vec3);
  std::vector<std::string> motion(sent_.size(), std::string(1, flags));
  std::vector<std::size_t> sizes(sent_.size());
  for (std::size_t r = 0; r < sent_.size(); ++r) {
    for (std::uint32_t i : sent_[r]) put(motion[r], p.position[i]), put(motion[r], p.velocity[i]), put(motion[r], p.omega[i]);
    sizes[r] = 1 + kMotion * ghosts_from_[r];
  }
  const std::vector<std::string> received = exchange(motion, &sizes);
  char any = 0;
  for (std::size_t r = 0; r < received.size(); ++r) {
    any = static_cast<char>(any | received[r][0]);
    std::size_t at = 1, k = received_from_[r];
    for (; at < received[r].size(); ++k) {
      p.position[k] = take<Vec3>(received[r], at);
      p.velocity[k] = take<Vec3>(received[r], at);
      p.omega[k] = take<Vec3>(received[r], at);
    }
  }
  return any;
}

bool Decomposition::update(World& world, bool lost) {
  constexpr char kMoved = 1, kLost = 2;  // the flags of refresh_ghosts
  const Particles& p = world.particles;
  const double limit2 = 0.25 * skin_ * skin_;
  bool moved = false;
  for (std::size_t i = 0; i < world.owned() && !moved && !lost; ++i)
    moved = norm2(world.domain.separation(p.position[i], arranged_at_[i])) > limit2;
  const char flags = refresh_ghosts(world, static_cast<char>((moved ? kMoved : 0) | (lost ? kLost : 0)));
  if (flags & kLost) throw StepAbandoned();  // the state stays as the drift left it, for the failing frame
  const bool rearranged = std::exchange(rearranged_, false);  // the same on every process
  links_kept_ = false;  // an evaluation follows
  if (!(flags & kMoved)) return rearranged;  // no particle has moved half the skin, on any process
  hand_over(world, {});
  return true;
}

void Decomposition::agree_any(std::vector<char>& flags) const { comm_.any_each(flags); }

void Decomposition::add(World& world, Particles arrivals, const ForceField& forces) {
  if (!links_kept_) {  // the results of the contacts as evaluated, before the lists are arranged again
    evaluated_links_ = link_records(world, forces, evaluated_link_count_);
    links_kept_ = true;
  }
  for (double r : arrivals.radius) largest_radius_ = std::max(largest_radius_, r);  // alike on every process
  width_ = reach_per_radius_ * largest_radius_ + skin_;
  refresh_ghosts(world, 0);  // the partners' owners below are read from the ghosts' positions
  hand_over(world, arrivals);
  rearranged_ = true;
}

void Decomposition::remove(World& world, const std::vector<std::int64_t>& ids) {
  refresh_ghosts(world, 0);  // the partners' owners in the hand-over are read from the ghosts' positions
  const std::vector<std::int64_t>& id = world.particles.id;
  std::vector<char> gone(id.size());
  for (std::size_t i = 0; i < id.size(); ++i) gone[i] = std::binary_search(ids.begin(), ids.end(), id[i]);
  remove_particles(world, gone);
  hand_over(world, {});
  rearranged_ = true;
}

std::vector<std::string> Decomposition::gather_all(const std::string& bytes) {
  return exchange(std::vector<std::string>(static_cast<std::size_t>(comm_.size()), bytes));
}

void Decomposition::hand_over(World& world, const Particles& arrivals) {
  rebalance(world, false);
  const Particles& p = world.particles;
  // Every owned particle goes to the process of its subdomain (itself, mostly), with the
  // touching contacts of each of its particles: their histories are this process's to give.
  // Each process takes the arrivals in its subdomain.
  const std::size_t processes = static_cast<std::size_t>(comm_.size());
  std::vector<Parcel> parcels(processes);
  std::vector<int> owner(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) owner[i] = grid_.owner(p.position[i]);
  for (std::size_t i = 0; i < world.owned(); ++i) {
    Parcel& to = parcels[static_cast<std::size_t>(owner[i])];
    pack(p, i, to.particles);
    ++to.particle_count;
  }
  Parcel& mine = parcels[static_cast<std::size_t>(comm_.rank())];
  for (std::size_t i = 0; i < arrivals.size(); ++i)
    if (grid_.owner(arrivals.position[i]) == comm_.rank()) pack(arrivals, i, mine.particles), ++mine.particle_count;
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
  const std::vector<std::string> received = exchange(out);
  Particles owned;
  std::vector<ContactLink> links;
  for (const std::string& bytes : received)
    read_parcel(bytes, owned, [&](const std::string& b, std::size_t& at) { links.push_back(take<ContactLink>(b, at)); });
  arrange(world, std::move(owned), std::move(links));
}

Decomposition::Gathered Decomposition::gathered(const World& world, const ForceField& forces) const {
  // Each touching contact of the owned particles with its result; a pair across a cut comes
  // from both its processes, alike (the same bits), and is kept once.
  Parcel mine;
  for (std::size_t i = 0; i < world.owned(); ++i) pack(world.particles, i, mine.particles), ++mine.particle_count;
  if (links_kept_) mine.links = evaluated_links_, mine.link_count = evaluated_link_count_;
  else mine.links = link_records(world, forces, mine.link_count);
  Gathered all;
  World& w = all.world;
  w.domain = world.domain;
  w.walls = world.walls;
  w.wall_elements = world.wall_elements;
  w.dt = world.dt, w.time = world.time, w.step = world.step;
  w.source_ids = world.source_ids;
  const std::vector<std::string> parts = comm_.gather(mine.bytes());
  const ProcessLoad load{world.owned(), world.ghosts, world.contacts.pairs().size(), bytes_sent_, arrangements_};
  std::string load_bytes;
  put(load_bytes, load);
  for (const std::string& bytes : comm_.gather(load_bytes)) {
    std::size_t at = 0;
    all.loads.push_back(take<ProcessLoad>(bytes, at));
  }
  if (parts.empty()) return all;
  std::vector<std::pair<ContactLink, ContactResult>> records;
  for (const std::string& bytes : parts)
    read_parcel(bytes, w.particles, [&](const std::string& b, std::size_t& at) {
      const auto l = take<ContactLink>(b, at);
      records.emplace_back(l, take<ContactResult>(b, at));
    });
  in_id_order(w.particles);
  std::sort(records.begin(), records.end(), [](const auto& x, const auto& y) { return link_key(x.first) < link_key(y.first); });
  records.erase(std::unique(records.begin(), records.end(),
                            [](const auto& x, const auto& y) { return link_key(x.first) == link_key(y.first); }),
                records.end());
  std::vector<ContactLink> links;
  for (const auto& [l, r] : records) {
    links.push_back(l);
    (l.wall >= 0 ? all.wall_results : all.pair_results).push_back(r);
  }
  assign_contacts(w.contacts, std::move(links), w.particles, w.particles.size());
  return all;
}

}  // namespace tsubu
