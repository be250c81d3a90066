#include "tsubu/app/checkpoint.hpp"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "tsubu/core/hash.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

// A new particle array, contact-history field or checkpoint field must be added to the format
// (and kCheckpointVersion raised, and docs/reliability.md's format table updated); these
// catch additions that forget it.
static_assert(sizeof(Particles) == 12 * sizeof(std::vector<double>),
              "Particles changed: write the new array in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(ContactHistory) == 8 * sizeof(double),
              "ContactHistory changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(OutputState) == sizeof(std::int64_t) + sizeof(OutputState::pvd) + 3 * sizeof(std::uint64_t),
              "OutputState changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(EnergyWatch::State) == 3 * sizeof(double),
              "EnergyWatch::State changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(Checkpoint) == 4 * sizeof(std::string) + sizeof(std::vector<std::string>) + 4 * sizeof(std::uint64_t) +
                                        3 * sizeof(double) + sizeof(std::int64_t) + sizeof(OutputState) +
                                        sizeof(Particles) + 2 * sizeof(std::vector<Contact>) +
                                        2 * sizeof(std::vector<Vec3>) + sizeof(EnergyWatch::State) +
                                        sizeof(Checkpoint::BlockSteps) + sizeof(Checkpoint::Inflow) +
                                        sizeof(Checkpoint::Record) + sizeof(Checkpoint::Departed),
              "Checkpoint changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(HermiteState) == 6 * sizeof(std::vector<double>) &&
                  sizeof(BlockStepStats) == 2 * sizeof(std::uint64_t) + 3 * sizeof(std::vector<std::uint64_t>) &&
                  sizeof(Checkpoint::BlockSteps) == 2 * sizeof(std::uint64_t) + sizeof(HermiteState) +
                                                       2 * sizeof(std::vector<double>) + sizeof(BlockStepStats),
              "the block-step state changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(Checkpoint::Inflow) == 2 * sizeof(std::uint64_t) + sizeof(std::string),
              "the inflow section changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(Checkpoint::Record) == sizeof(std::uint64_t) + sizeof(Checkpoint::Record::source_ids) +
                                                sizeof(double) + 2 * sizeof(std::int64_t),
              "the record section changed: write the new field in encode_checkpoint/decode_checkpoint");
static_assert(sizeof(int) == 4 && sizeof(double) == 8, "the format stores int as 32 and double as 64 bits");
static_assert(std::endian::native == std::endian::little, "checkpoints are little-endian");

namespace {

constexpr char kMagic[8] = {'T', 'S', 'U', 'B', 'U', 'C', 'K', 'P'};
constexpr std::uint32_t kByteOrderMark = 0x01020304u;
constexpr std::size_t kHeaderSize = 32;

// The 32-byte header: magic, version, byte-order mark, payload size, FNV-1a 64 of the payload.
std::string header(std::uint64_t size, std::uint64_t sum) {
  std::string out(kHeaderSize, '\0');
  char* h = out.data();
  std::memcpy(h, kMagic, 8);
  const std::uint32_t version = kCheckpointVersion;
  std::memcpy(h + 8, &version, 4);
  std::memcpy(h + 12, &kByteOrderMark, 4);
  std::memcpy(h + 16, &size, 8);
  std::memcpy(h + 24, &sum, 8);
  return out;
}

// Appends the payload to a string, or streams it to a file through a small buffer (a
// checkpoint of a large run must not hold a second copy of the state in memory); keeps the
// size and the running FNV-1a checksum.
class Writer {
 public:
  explicit Writer(std::string* out) : bytes_(out) {}
  explicit Writer(int fd, const std::filesystem::path& name) : fd_(fd), name_(name) {}
  std::uint64_t size = 0, checksum = kFnv1aStart;
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    raw(&v, sizeof v);
  }
  void u64(std::uint64_t v) { pod(v); }
  void str(const std::string& s) {
    u64(s.size());
    raw(s.data(), s.size());
  }
  template <class T>
  void array(const std::vector<T>& v) {  // the count is written once, before all arrays
    raw(v.data(), v.size() * sizeof(T));
  }
  // A per-particle array in the file's order: v[order[0]], v[order[1]], ...
  template <class T>
  void array(const std::vector<T>& v, const std::vector<std::size_t>& order) {
    for (std::size_t k : order) raw(&v[k], sizeof(T));
  }
  void contacts(const std::vector<Contact>& list) {
    u64(list.size());
    for (const Contact& c : list) {
      pod(c.i);
      pod(c.j);
      pod(c.history.xi);
      pod(c.history.normal);
      pod(c.history.rolling);
    }
  }
  void flush() {
    write_all(fd_, buffer_.data(), buffer_.size(), name_);
    buffer_.clear();
  }

 private:
  std::string* bytes_ = nullptr;
  int fd_ = -1;
  std::filesystem::path name_;
  std::string buffer_;
  void raw(const void* data, std::size_t n) {
    if (n == 0) return;
    const char* d = static_cast<const char*>(data);
    checksum = fnv1a64({d, n}, checksum);
    size += n;
    std::string& out = bytes_ ? *bytes_ : buffer_;
    out.append(d, n);
    if (!bytes_ && buffer_.size() >= (1u << 20)) flush();
  }
};

class Reader {
 public:
  Reader(const std::string& b, std::size_t begin) : bytes_(b), pos_(begin) {}
  template <class T>
  T pod() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  std::uint64_t u64() { return pod<std::uint64_t>(); }
  // An element count, checked against the bytes left so a corrupt count cannot allocate much.
  std::size_t count(std::size_t bytes_each) {
    const std::uint64_t n = u64();
    if (bytes_each > 0 && n > (bytes_.size() - pos_) / bytes_each) throw CheckpointError("a count exceeds the file size");
    return static_cast<std::size_t>(n);
  }
  std::string str() {
    const std::size_t n = count(1);
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  template <class T>
  void array(std::vector<T>& v, std::size_t n) {
    need(n * sizeof(T));
    v.resize(n);
    if (n > 0) std::memcpy(v.data(), bytes_.data() + pos_, n * sizeof(T));  // data() may be null
    pos_ += n * sizeof(T);
  }
  void contacts(std::vector<Contact>& list) {
    list.resize(count(2 * 4 + 8 * 8));
    for (Contact& c : list) {
      c.i = pod<std::uint32_t>();
      c.j = pod<std::uint32_t>();
      c.touching = true;
      c.history.xi = pod<Vec3>();
      for (double& h : c.history.normal) h = pod<double>();
      c.history.rolling = pod<Vec3>();
    }
  }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  const std::string& bytes_;
  std::size_t pos_;
  void need(std::size_t n) const {
    if (n > bytes_.size() - pos_) throw CheckpointError("the payload ends early");
  }
};

// The particles are written in the order of their ids and only the touching contacts, each
// pair from its particle with the smaller id (the contact list's first particle; in the
// file, the smaller index) and both lists sorted by (i, j) in that numbering: the file does
// not depend on how the run numbered its particles (a spatial sort) nor on when it last
// built its lists (the entries that do not touch carry an empty history), so that runs of
// the same physics write the same bytes. The contact histories are stored from the smaller
// id already (ContactList) and need no turn.
struct FileOrder {
  std::vector<std::size_t> particles;  // particles[k]: the index of the particle written k-th
  std::vector<Contact> pairs, walls;   // renumbered to the file's order

  explicit FileOrder(const Checkpoint& c) : particles(c.particles.in_id_order()) {
    std::vector<std::uint32_t> position(particles.size());
    for (std::size_t k = 0; k < particles.size(); ++k) position[particles[k]] = static_cast<std::uint32_t>(k);
    for (Contact k : c.pair_contacts) {
      if (!k.touching) continue;
      k.i = position[k.i], k.j = position[k.j];
      if (k.i > k.j) std::swap(k.i, k.j);  // a pair given the other way round (not by a contact list)
      pairs.push_back(k);
    }
    for (Contact k : c.wall_contacts)
      if (k.touching) k.i = position[k.i], walls.push_back(k);
    const auto by_pair = [](const Contact& a, const Contact& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; };
    std::sort(pairs.begin(), pairs.end(), by_pair);
    std::sort(walls.begin(), walls.end(), by_pair);
  }
};

void write_payload(const Checkpoint& c, Writer& w) {
  const FileOrder order(c);
  w.str(c.engine_version);
  w.str(c.run_id);
  w.str(c.scenario_path);
  w.str(c.scenario_text);
  w.u64(c.overrides.size());
  for (const auto& o : c.overrides) w.str(o);
  w.u64(c.scenario_hash);
  w.pod(c.step);
  w.pod(c.time);
  w.pod(c.dt);
  w.u64(c.counters.evaluations);
  w.u64(c.counters.particle_evaluations);
  w.u64(c.counters.rebuilds);
  w.pod(c.wall_seconds);
  w.pod(c.output.frame);
  w.u64(c.output.pvd.size());
  for (const auto& [t, name] : c.output.pvd) w.pod(t), w.str(name);
  w.u64(c.output.series_bytes);
  w.u64(c.output.track_bytes);
  const Particles& p = c.particles;
  w.u64(p.size());
  p.for_each_array([&](const auto& array) { w.array(array, order.particles); });
  w.contacts(order.pairs);
  w.contacts(order.walls);
  w.u64(c.wall_points.size());
  w.array(c.wall_points);
  w.array(c.wall_velocities);
  w.pod(static_cast<std::uint8_t>(c.energy_watch.started));
  w.pod(c.energy_watch.reference);
  w.pod(c.energy_watch.active_max);
  if (c.block.present) {  // n entries each, n = the particle count above
    const Checkpoint::BlockSteps& b = c.block;
    w.pod(std::uint8_t{1});
    b.state.for_each_array([&](const auto& array) { w.array(array, order.particles); });
    w.array(b.list_positions, order.particles);
    w.array(b.list_reach, order.particles);
    w.pod(static_cast<std::uint8_t>(b.lists_stale));
    w.u64(b.stats.block_times);
    w.u64(b.stats.wakes);
    w.u64(b.stats.evaluations.size());
    w.array(b.stats.evaluations);
    w.array(b.stats.set_by_own);  // kStepRules entries each
    w.array(b.stats.set_by_cluster);
  }
  if (c.inflow.present) {
    w.pod(std::uint8_t{2});
    w.pod(c.inflow.first_id);
    w.str(c.inflow.state);
  }
  if (c.record.present) {
    w.pod(std::uint8_t{3});
    w.u64(c.record.source_ids.size());
    for (const auto& [first, end] : c.record.source_ids) w.pod(first), w.pod(end);
    w.pod(c.record.loop_seconds);
    w.pod(c.record.loop_steps);
    w.pod(c.record.loop_sessions);
  }
  if (c.departed.present) {
    w.pod(std::uint8_t{4});
    w.pod(c.departed.totals.count);
    w.pod(c.departed.totals.mass);
    w.pod(c.departed.totals.inflow_mass);
    w.u64(c.output.outflow_bytes);
  }
}

}  // namespace

std::string encode_checkpoint(const Checkpoint& c) {
  std::string payload;
  Writer w(&payload);
  write_payload(c, w);
  return header(w.size, w.checksum) + payload;
}

Checkpoint decode_checkpoint(const std::string& bytes) {
  if (bytes.size() < kHeaderSize) throw CheckpointError("truncated: shorter than the header");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) throw CheckpointError("not a tsubu checkpoint (bad magic)");
  std::uint32_t version, bom;
  std::uint64_t size, sum;
  std::memcpy(&version, bytes.data() + 8, 4);
  std::memcpy(&bom, bytes.data() + 12, 4);
  std::memcpy(&size, bytes.data() + 16, 8);
  std::memcpy(&sum, bytes.data() + 24, 8);
  if (bom != kByteOrderMark) throw CheckpointError("written on a machine of the other byte order");
  if (version != kCheckpointVersion)
    throw CheckpointError("format version " + std::to_string(version) + ", this tsubu reads version " +
                          std::to_string(kCheckpointVersion) +
                          (version < kCheckpointVersion ? " (an older tsubu wrote it: resume it with that tsubu, or run again)" : ""));
  if (size != bytes.size() - kHeaderSize)
    throw CheckpointError("truncated: the header announces " + std::to_string(size) + " payload bytes, the file has " +
                          std::to_string(bytes.size() - kHeaderSize));
  if (fnv1a64({bytes.data() + kHeaderSize, size}) != sum) throw CheckpointError("corrupted: checksum mismatch");

  Reader r(bytes, kHeaderSize);
  Checkpoint c;
  c.engine_version = r.str();
  c.run_id = r.str();
  c.scenario_path = r.str();
  c.scenario_text = r.str();
  c.overrides.resize(r.count(8));
  for (auto& o : c.overrides) o = r.str();
  c.scenario_hash = r.u64();
  c.step = r.pod<std::int64_t>();
  c.time = r.pod<double>();
  c.dt = r.pod<double>();
  c.counters.evaluations = r.u64();
  c.counters.particle_evaluations = r.u64();
  c.counters.rebuilds = r.u64();
  c.wall_seconds = r.pod<double>();
  c.output.frame = r.pod<std::int64_t>();
  c.output.pvd.resize(r.count(16));
  for (auto& [t, name] : c.output.pvd) t = r.pod<double>(), name = r.str();
  c.output.series_bytes = r.u64();
  c.output.track_bytes = r.u64();
  Particles& p = c.particles;
  std::size_t bytes_each = 0;  // of one particle: the element sizes of its arrays
  p.for_each_array([&](const auto& array) { bytes_each += sizeof(array[0]); });
  const std::size_t n = r.count(bytes_each);
  p.for_each_array([&](auto& array) { r.array(array, n); });
  r.contacts(c.pair_contacts);
  r.contacts(c.wall_contacts);
  const std::size_t n_walls = r.count(2 * 24);
  r.array(c.wall_points, n_walls);
  r.array(c.wall_velocities, n_walls);
  const auto started = r.pod<std::uint8_t>();
  if (started > 1) throw CheckpointError("corrupted: energy-watch flag is neither 0 nor 1");
  c.energy_watch = {started == 1, r.pod<double>(), r.pod<double>()};
  // Optional sections, each once and in this order: 1 block steps, 2 inflow, 3 the record,
  // 4 the departed grains.
  int section = r.at_end() ? -1 : r.pod<std::uint8_t>();
  if (section == 1) {
    Checkpoint::BlockSteps& b = c.block;
    b.present = true;
    b.state.for_each_array([&](auto& array) { r.array(array, n); });
    r.array(b.list_positions, n);
    r.array(b.list_reach, n);
    const auto stale = r.pod<std::uint8_t>();
    if (stale > 1) throw CheckpointError("corrupted: the lists' stale flag is neither 0 nor 1");
    b.lists_stale = stale == 1;
    b.stats.block_times = r.u64();
    b.stats.wakes = r.u64();
    r.array(b.stats.evaluations, r.count(8));
    r.array(b.stats.set_by_own, kStepRules);
    r.array(b.stats.set_by_cluster, kStepRules);
    section = r.at_end() ? -1 : r.pod<std::uint8_t>();
  }
  if (section == 2) {
    c.inflow.present = true;
    c.inflow.first_id = r.pod<std::int64_t>();
    c.inflow.state = r.str();
    section = r.at_end() ? -1 : r.pod<std::uint8_t>();
  }
  if (section == 3) {
    Checkpoint::Record& record = c.record;
    record.present = true;
    record.source_ids.resize(r.count(16));
    for (auto& [first, end] : record.source_ids) first = r.pod<std::int64_t>(), end = r.pod<std::int64_t>();
    record.loop_seconds = r.pod<double>();
    record.loop_steps = r.pod<std::int64_t>();
    record.loop_sessions = r.pod<std::int64_t>();
    section = r.at_end() ? -1 : r.pod<std::uint8_t>();
  }
  if (section == 4) {
    c.departed.present = true;
    c.departed.totals.count = r.pod<std::int64_t>();
    c.departed.totals.mass = r.pod<double>();
    c.departed.totals.inflow_mass = r.pod<double>();
    c.output.outflow_bytes = r.u64();
    section = r.at_end() ? -1 : r.pod<std::uint8_t>();
  }
  if (section != -1) throw CheckpointError("corrupted: unknown section " + std::to_string(section) + " after the energy watch");
  if (!r.at_end()) throw CheckpointError("bytes left after the payload");
  // The file's order (FileOrder): what was written so is read back as the same bytes.
  for (std::size_t k = 1; k < n; ++k)
    if (p.id[k] < p.id[k - 1]) throw CheckpointError("the particles are not in the order of their ids");
  const auto check = [&](const std::vector<Contact>& list, const char* what, bool pairs) {
    for (std::size_t k = 0; k < list.size(); ++k) {
      const Contact& a = list[k];
      if (a.i >= n || (pairs && a.j >= n)) throw CheckpointError(std::string("a ") + what + " names a particle that does not exist");
      if (pairs && a.i >= a.j) throw CheckpointError("a pair contact is not listed from its first particle");
      if (k > 0 && !(list[k - 1].i < a.i || (list[k - 1].i == a.i && list[k - 1].j < a.j)))
        throw CheckpointError(std::string("the ") + what + "s are not sorted by (i, j)");
    }
  };
  check(c.pair_contacts, "pair contact", true);
  check(c.wall_contacts, "wall contact", false);
  return c;
}

std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& dir) {
  std::vector<std::pair<std::int64_t, std::filesystem::path>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() <= 10 || name.rfind("step_", 0) != 0 || e.path().extension() != ".tsbk") continue;
    const std::string digits = name.substr(5, name.size() - 10);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    found.emplace_back(std::stoll(digits), e.path());
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::filesystem::path> out;
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const Checkpoint& c, int keep) {
  std::filesystem::create_directories(dir);
  char name[40];
  std::snprintf(name, sizeof name, "step_%012lld.tsbk", static_cast<long long>(c.step));
  const std::filesystem::path file = dir / name;
  // Streamed: the header's size and checksum are known at the end and written last.
  write_file_atomically(file, [&](int fd) {
    write_all(fd, header(0, 0).data(), kHeaderSize, file);
    Writer w(fd, file);
    write_payload(c, w);
    w.flush();
    const std::string h = header(w.size, w.checksum);
    if (::pwrite(fd, h.data(), kHeaderSize, 0) != static_cast<ssize_t>(kHeaderSize)) throw_write_error("write", file, errno);
  });
  const auto all = list_checkpoints(dir);
  for (std::size_t k = static_cast<std::size_t>(std::max(keep, 1)); k < all.size(); ++k) std::filesystem::remove(all[k]);
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.path().extension() == ".tmp" && e.path() != file) std::filesystem::remove(e.path(), ec);
  return file;
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw CheckpointError("cannot open the file");
  std::ostringstream s;
  s << in.rdbuf();
  return decode_checkpoint(s.str());
}

World world_of_checkpoint(const Scenario& sc, Checkpoint& c, const std::filesystem::path& file) {
  World world = build_empty_world(sc);
  world.particles = std::move(c.particles);
  world.contacts.assign(std::move(c.pair_contacts), std::move(c.wall_contacts), world.particles);
  world.step = c.step;
  world.time = c.time;
  world.source_ids = c.record.source_ids;  // none in a checkpoint of an older tsubu
  for (const Contact& k : world.contacts.walls())
    if (k.j >= world.element_count()) throw std::runtime_error(file.string() + ": a wall contact names a wall the scenario lacks");
  if (c.wall_points.size() != world.walls.size())
    throw std::runtime_error(file.string() + ": it stores " + std::to_string(c.wall_points.size()) +
                             " walls, the scenario has " + std::to_string(world.walls.size()));
  for (std::size_t k = 0; k < world.walls.size(); ++k) {
    world.walls[k].point = c.wall_points[k], world.walls[k].velocity = c.wall_velocities[k];  // moving walls
    if (c.step > 0) world.walls[k].surface_during(c.time - 0.5 * world.dt);  // as the last step set it
    world.walls[k].turn_to(c.time);  // a turning mesh
  }
  return world;
}

}  // namespace tsubu
