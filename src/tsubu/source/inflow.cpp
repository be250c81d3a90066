#include "tsubu/source/inflow.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "tsubu/core/error.hpp"
#include "tsubu/core/random.hpp"
#include "tsubu/search/sphere_grid.hpp"
#include "tsubu/source/release.hpp"
#include "tsubu/source/size_moments.hpp"

namespace tsubu {

namespace {

constexpr int kAttempts = 100000;         // placements tried per grain
constexpr double kGrainsPerSlab = 50;     // the slab height holds about this many grains

// The column in its own frame: x, y over the base (periodic), height above z_c.
Domain column_frame(const InflowColumn& c) {
  return {{c.x_low, c.y_low, 0}, {c.x_low + c.length_x, c.y_low + c.length_y, 1}, {true, true, false}};
}

}  // namespace

double InflowColumn::mass_flux() const { return density * solid_fraction * area() * speed; }

double InflowColumn::grains_per_second() const { return mass_flux() / (density * mean_grain_volume(sizes)); }

double InflowColumn::free_fall_time() const { return gravity > 0 ? std::sqrt(std::sqrt(area()) / gravity) : 0.0; }

double InflowColumn::flux_number() const { return mass_flux() * free_fall_time(); }

namespace {

double grains_per_height(const InflowColumn& c) { return c.solid_fraction * c.area() / mean_grain_volume(c.sizes); }

}  // namespace

double InflowColumn::slab_height() const { return std::max(4 * sizes.largest(), kGrainsPerSlab / grains_per_height(*this)); }

double InflowColumn::slab_grains() const { return (slab_height() + 2 * sizes.largest()) * grains_per_height(*this); }

InflowStream::InflowStream(const InflowColumn& column, std::uint64_t seed)
    : column_(column), seed_(mix64(seed ^ 0x1f10c0de5eed5ULL)), slab_height_(column.slab_height()), band_(column.sizes.largest()) {
  slab_ = slab(0);
}

// One region of the column, heights [lo, hi): diameters up to phi_0 of its volume on
// average (the last one kept with the probability of the volume still missing over its
// own), placed largest first without overlap against `grid`, then their spins.
void InflowStream::fill(std::uint64_t region, double lo, double hi, SphereGrid& grid, std::vector<Placed>& out) const {
  Random rng(mix64(seed_ + mix64(region)));
  const double target = column_.solid_fraction * column_.area() * (hi - lo);
  std::vector<double> diameters;
  for (double volume = 0;;) {
    const double d = column_.sizes.sample(rng), v = M_PI / 6 * d * d * d;
    if (volume + v >= target) {
      if (rng.uniform() * v < target - volume) diameters.push_back(d);
      break;
    }
    diameters.push_back(d);
    volume += v;
  }
  std::sort(diameters.rbegin(), diameters.rend());
  const std::size_t first = out.size();
  for (double d : diameters) {
    int attempt = 0;
    for (; attempt < kAttempts; ++attempt) {
      const Vec3 x{rng.uniform(column_.x_low, column_.x_low + column_.length_x),
                   rng.uniform(column_.y_low, column_.y_low + column_.length_y), rng.uniform(lo, hi)};
      if (grid.overlaps(x, 0.5 * d)) continue;
      grid.add(x, 0.5 * d);
      out.push_back({d, x.x, x.y, x.z, {}});
      break;
    }
    if (attempt == kAttempts)
      throw NumericalError("inflow: no place without overlap for a grain of the virtual column after " +
                           std::to_string(kAttempts) + " tries; lower its solid_fraction");
  }
  if (column_.omega_star_rms > 0)  // each component normal, sd omega_rms = 2 u_r Omega*_rms / d
    for (std::size_t k = first; k < out.size(); ++k) {
      const double rms = 2 * column_.speed * column_.omega_star_rms / out[k].diameter;
      out[k].omega = Vec3{rng.normal(), rng.normal(), rng.normal()} * rms;
    }
}

std::vector<InflowStream::Placed> InflowStream::band(std::int64_t k) const {
  const double mid = static_cast<double>(k) * slab_height_;
  SphereGrid grid(column_frame(column_), {column_.x_low, column_.y_low, mid - 2 * band_},
                  {column_.x_low + column_.length_x, column_.y_low + column_.length_y, mid + 2 * band_}, {true, true, false},
                  band_);
  std::vector<Placed> out;
  fill(2 * static_cast<std::uint64_t>(k), mid - band_, mid + band_, grid, out);
  return out;
}

std::vector<InflowStream::Placed> InflowStream::slab(std::int64_t k) const {
  const double bottom = static_cast<double>(k) * slab_height_, top = bottom + slab_height_;
  std::vector<Placed> out = k > 0 ? band(k) : std::vector<Placed>{};
  const std::vector<Placed> above = band(k + 1);
  SphereGrid grid(column_frame(column_), {column_.x_low, column_.y_low, bottom - 2 * band_},
                  {column_.x_low + column_.length_x, column_.y_low + column_.length_y, top + 2 * band_}, {true, true, false},
                  band_);
  for (const std::vector<Placed>* region : {&std::as_const(out), &above})
    for (const Placed& p : *region) grid.add({p.x, p.y, p.height}, 0.5 * p.diameter);
  fill(2 * static_cast<std::uint64_t>(k) + 1, k > 0 ? bottom + band_ : 0.0, top - band_, grid, out);
  std::stable_sort(out.begin(), out.end(), [](const Placed& a, const Placed& b) { return a.height < b.height; });
  return out;
}

std::vector<NewGrain> InflowStream::due(double t) {
  std::vector<NewGrain> out = waiting_at(state_, t);
  while (!state_.limit_reached) {
    if (state_.next == static_cast<std::int64_t>(slab_.size())) {
      slab_ = slab(++state_.slab);
      state_.next = 0;
      continue;
    }
    const Placed& p = slab_[static_cast<std::size_t>(state_.next)];
    const double arrival = p.height / column_.speed;  // paper Eq. 27
    if (arrival > t) break;
    if (!release(state_, {state_.released, p.diameter, p.x, p.y, arrival, p.omega, 0}, grain_mass(column_.density, p.diameter),
                 column_.mass_limit, out))
      break;
  }
  return out;
}

void InflowStream::delay(NewGrain g) { turn_back(state_, g); }

void InflowStream::restore(const State& s) {
  if (s.slab < 0) throw std::runtime_error("inflow state: slab " + std::to_string(s.slab) + " does not exist");
  std::vector<Placed> restored = slab(s.slab);
  if (s.next < 0 || s.next > static_cast<std::int64_t>(restored.size()))
    throw std::runtime_error("inflow state: grain " + std::to_string(s.next) + " of slab " + std::to_string(s.slab) +
                             " does not exist (the slab has " + std::to_string(restored.size()) + ")");
  slab_ = std::move(restored);
  state_ = s;
}

std::vector<std::pair<std::string, double>> inflow_rates(const InflowColumn& c) {
  return {{"inflow_F", c.mass_flux()},     {"inflow_grains_per_s", c.grains_per_second()},
          {"inflow_phi_0", c.solid_fraction}, {"inflow_Q", c.flux_number()},
          {"inflow_t_f", c.free_fall_time()}, {"inflow_u_r", c.speed},
          {"inflow_z_c", c.entry_height}};
}

std::vector<std::pair<std::string, double>> inflow_counts(const InflowStream::State& s) {
  return {{"inflow_released", static_cast<double>(s.released)},
          {"inflow_mass_released", s.mass_released},
          {"inflow_delays", static_cast<double>(s.delays)},
          {"inflow_delayed_grains", static_cast<double>(s.delayed_grains)},
          {"inflow_waiting", static_cast<double>(s.waiting.size())}};
}

namespace {

constexpr char kStateMagic[8] = {'T', 'S', 'I', 'N', 'F', 'L', 'O', '1'};

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <class T>
T take(std::string_view& in) {
  if (in.size() < sizeof(T)) throw std::runtime_error("inflow state: the bytes end too early");
  T v;
  std::memcpy(&v, in.data(), sizeof v);
  in.remove_prefix(sizeof v);
  return v;
}

}  // namespace

std::string encode_inflow_state(const InflowStream::State& s) {
  std::string out(kStateMagic, sizeof kStateMagic);
  put(out, s.slab), put(out, s.next), put(out, s.released), put(out, s.mass_released);
  put(out, static_cast<std::uint8_t>(s.limit_reached)), put(out, s.delays), put(out, s.delayed_grains);
  put(out, static_cast<std::uint64_t>(s.waiting.size()));
  for (const NewGrain& g : s.waiting)
    put(out, g.serial), put(out, g.diameter), put(out, g.x), put(out, g.y), put(out, g.arrival), put(out, g.omega),
        put(out, g.delays);
  return out;
}

InflowStream::State decode_inflow_state(std::string_view in) {
  if (in.substr(0, sizeof kStateMagic) != std::string_view(kStateMagic, sizeof kStateMagic))
    throw std::runtime_error("inflow state: not an inflow state (wrong magic)");
  in.remove_prefix(sizeof kStateMagic);
  InflowStream::State s;
  s.slab = take<std::int64_t>(in), s.next = take<std::int64_t>(in), s.released = take<std::int64_t>(in);
  s.mass_released = take<double>(in);
  s.limit_reached = take<std::uint8_t>(in) != 0;
  s.delays = take<std::int64_t>(in), s.delayed_grains = take<std::int64_t>(in);
  const auto waiting = take<std::uint64_t>(in);
  if (waiting > in.size()) throw std::runtime_error("inflow state: the bytes end too early");
  for (std::uint64_t k = 0; k < waiting; ++k) {
    NewGrain g;
    g.serial = take<std::int64_t>(in), g.diameter = take<double>(in), g.x = take<double>(in), g.y = take<double>(in);
    g.arrival = take<double>(in), g.omega = take<Vec3>(in), g.delays = take<std::int32_t>(in);
    s.waiting.push_back(g);
  }
  if (!in.empty()) throw std::runtime_error("inflow state: " + std::to_string(in.size()) + " bytes left over");
  return s;
}

SphereGrid entry_neighbours(const Domain& domain, std::span<const Vec3> position, std::span<const double> radius,
                            double lowest, double entering_radius) {
  std::vector<std::size_t> near;
  double r_max = entering_radius, top = lowest;
  for (std::size_t i = 0; i < position.size(); ++i)
    if (position[i].z + radius[i] > lowest - entering_radius) {
      near.push_back(i);
      r_max = std::max(r_max, radius[i]);
      top = std::max(top, position[i].z);
    }
  SphereGrid grid(domain, {domain.lower.x, domain.lower.y, lowest - entering_radius - r_max},
                  {domain.upper.x, domain.upper.y, top + r_max}, {domain.periodic[0], domain.periodic[1], false},
                  entering_radius + r_max);
  for (std::size_t i : near) grid.add(position[i], radius[i]);
  return grid;
}

SphereGrid InflowStream::neighbours(const Domain& domain, std::span<const Vec3> position, std::span<const double> radius,
                                    const std::vector<NewGrain>& due, double t) const {
  double lowest = column_.entry_height;
  for (const NewGrain& g : due) lowest = std::min(lowest, this->position(g, t).z);
  return entry_neighbours(domain, position, radius, lowest, 0.5 * column_.sizes.largest());
}

}  // namespace tsubu
