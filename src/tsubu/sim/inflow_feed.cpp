#include "tsubu/sim/inflow_feed.hpp"

#include <map>

#include "tsubu/core/exact_sum.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {

namespace {

std::variant<InflowStream, InsertionStream> stream_of(const Scenario& sc, const ParticleSource& src) {
  if (src.kind == ParticleSource::Kind::insertion) return InsertionStream(insertion_of(sc, src), sc.seed);
  return InflowStream(inflow_column(sc, src), sc.seed);
}

}  // namespace

InflowFeed::InflowFeed(const Scenario& sc, const ParticleSource& src, std::int64_t first_id)
    : stream_(stream_of(sc, src)), material_(src.material), first_id_(first_id) {}

void InflowFeed::admit(World& w) {
  std::visit([&](auto& s) { admit_due(s, w.time, w.domain, w.particles, material_, first_id_, w.walls); }, stream_);
}

void InflowFeed::admit(const World& w, Particles& arrivals, const OverlapAgreement& agree) {
  std::visit([&](auto& s) { admit_due(s, w.time, w.domain, w.walls, w.particles, w.owned(), arrivals, material_, first_id_, agree); },
             stream_);
}

const SizeDistribution& InflowFeed::sizes() const {
  if (const auto* column = std::get_if<InflowStream>(&stream_)) return column->column().sizes;
  return std::get<InsertionStream>(stream_).insertion().sizes;
}

bool InflowFeed::ended() const {
  return std::visit([](const auto& s) { return s.exhausted(); }, stream_);
}

std::vector<std::pair<std::string, double>> InflowFeed::rates() const {
  if (const auto* column = std::get_if<InflowStream>(&stream_)) return inflow_rates(column->column());
  return insertion_rates(std::get<InsertionStream>(stream_).insertion());
}

std::string InflowFeed::state() const {
  return std::visit([](const auto& s) { return encode_inflow_state(s.state()); }, stream_);
}

void InflowFeed::restore(std::string_view bytes) {
  std::visit([&](auto& s) { s.restore(decode_inflow_state(bytes)); }, stream_);
}

double InflowFeed::mass_in_box(const World& w) const {
  ExactSum mass;  // the same bits in any order of the particles (a split run's, a sorted run's)
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    if (w.particles.id[i] >= first_id_) mass += w.particles.mass[i];
  return mass.value();
}

namespace {

std::vector<std::pair<std::string, double>> results_of(std::vector<std::pair<std::string, double>> r,
                                                       const InflowStream::State& s, double measured_flux) {
  for (auto& count : inflow_counts(s)) r.push_back(std::move(count));
  r.emplace_back("inflow_F_measured", measured_flux);
  return r;
}

}  // namespace

std::vector<std::pair<std::string, double>> InflowFeed::results(double time, double mass_entered) const {
  return results_of(rates(), std::visit([](const auto& s) { return s.state(); }, stream_),
                    time > 0 ? mass_entered / time : 0.0);
}

std::string inflow_result_unit(const std::string& name) {
  static const std::map<std::string, std::string, std::less<>> units = {
      {"inflow_F", "kg/s"},  {"inflow_F_measured", "kg/s"}, {"inflow_grains_per_s", "1/s"},
      {"inflow_t_f", "s"},   {"inflow_u_r", "m/s"},         {"inflow_z_c", "m"}, {"inflow_Q", "kg"},
      {"inflow_mass_released", "kg"}};
  const auto it = units.find(name);
  return it == units.end() ? "" : it->second;
}

}  // namespace tsubu
