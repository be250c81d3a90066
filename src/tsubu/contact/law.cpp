#include "tsubu/contact/law.hpp"

#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace tsubu {

namespace {

// Every registered law is well formed (law.hpp), and the two registries' key names are
// apart: one scenario key feeds one law, and no law takes a generic key's name.
template <class... Laws>
constexpr bool well_formed_normal_laws(std::variant<Laws...>*) { return (well_formed_normal_law<Laws>() && ...); }
template <class... Laws>
constexpr bool well_formed_tangential_laws(std::variant<Laws...>*) { return (well_formed_tangential_law<Laws>() && ...); }
static_assert(well_formed_normal_laws(static_cast<NormalModel*>(nullptr)));
static_assert(well_formed_tangential_laws(static_cast<TangentialModel*>(nullptr)));
template <class... Laws>
constexpr bool well_formed_rolling_laws(std::variant<Laws...>*) { return (well_formed_rolling_law<Laws>() && ...); }
static_assert(well_formed_rolling_laws(static_cast<RollingModel*>(nullptr)));

// A key may be shared by the laws of one registry (the rolling laws' rolling_friction), which
// never take part in one pair together.
constexpr bool keys_apart() {
  const std::span<const LawTraits> registries[] = {kNormalLaws, kTangentialLaws, kRollingLaws};
  for (std::size_t r = 0; r < std::size(registries); ++r)
    for (const LawTraits& law : registries[r])
      for (const LawKey& k : law.keys) {
        for (std::string_view generic : {"normal", "tangential", "rolling", "restitution", "friction", "materials"})
          if (k.name == generic) return false;
        for (std::size_t other = r + 1; other < std::size(registries); ++other)
          for (const LawTraits& t : registries[other])
            if (t.key(k.name)) return false;
      }
  return true;
}
static_assert(keys_apart(), "a key name belongs to laws of two registries (normal, tangential, rolling), or is a generic key");

}  // namespace

double contact_time(const NormalModel& model, double m_eff, double r_eff, double u) {
  return std::visit([&](const auto& n) { return n.collision_time(m_eff, r_eff, u); }, model);
}

double peak_overlap(const NormalModel& model, double m_eff, double r_eff, double u) {
  return std::visit([&](const auto& n) { return n.peak_overlap(m_eff, r_eff, u); }, model);
}

std::string_view label_of(const NormalModel& model) {
  return std::visit([](const auto& n) { return traits_of<std::decay_t<decltype(n)>>().label; }, model);
}

bool exact_whatever_dt(const NormalModel& model) {
  return std::visit(
      [](const auto& n) {
        if constexpr (requires { n.exact_whatever_dt; }) return n.exact_whatever_dt;
        else return false;
      },
      model);
}

std::string_view when_not_finite(const NormalModel& model) {
  return std::visit(
      [](const auto& n) -> std::string_view {
        if constexpr (requires { n.when_not_finite; }) return n.when_not_finite;
        else return "";
      },
      model);
}

PairLaw make_pair_law(const ContactSpec& spec, const Material& a, const Material& b) {
  const LawTraits* normal = find_law(kNormalLaws, spec.normal);
  const LawTraits* tangential = find_law(kTangentialLaws, spec.tangential);
  const LawTraits* rolling = find_law(kRollingLaws, spec.rolling);
  if (normal && tangential && rolling)
    for (const auto& entry : spec.values)
      if (!normal->key(entry.first) && !tangential->key(entry.first) && !rolling->key(entry.first))
        throw std::invalid_argument("the key " + entry.first + " is not one of normal = \"" + spec.normal +
                                    "\", tangential = \"" + spec.tangential + "\" or rolling = \"" + spec.rolling + "\"");
  const MaterialPair pair{a, b, spec.restitution, spec.friction};
  PairLaw law{build_law<NormalModel>(spec.normal, pair, spec.values), NoFriction{},
              build_law<RollingModel>(spec.rolling, pair, spec.values)};
  const NormalSide side = std::visit([&](const auto& n) { return normal_side(n, pair.poisson()); }, law.normal);
  law.tangential = build_law<TangentialModel>(spec.tangential, pair, spec.values, side);
  return law;
}

bool LawTable::corrects_positions() const {
  for (const auto& l : laws)
    if (std::visit([](const auto& m) { return corrects_position_v<std::decay_t<decltype(m)>>; }, l.normal)) return true;
  return false;
}

bool LawTable::resists_rolling() const {
  for (const auto& l : laws)
    if (!std::holds_alternative<NoRolling>(l.rolling)) return true;
  return false;
}

std::string LawTable::without_rates() const {
  for (const auto& l : laws)
    if (!std::visit([](const auto& m) { return has_rates_v<std::decay_t<decltype(m)>>; }, l.normal))
      return "normal model " + std::string(label_of(l.normal));
  return "";
}

}  // namespace tsubu
