// The traits a contact law declares beside its struct (docs/contact-laws.md): its name as
// the scenario spells it, its scenario keys (kind, default, meaning), the integrators it runs
// with, its history slots and their swap rule, and a builder from the keys' values and the
// two materials. The loader (scenario/law_keys.cpp), the law table (law.hpp) and the time
// scales read them. Nothing here knows the scenario file: the laws stay below scenario/.
#pragma once
#include <array>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>

#include "tsubu/world/domain.hpp"

namespace tsubu {

// ---- Scenario keys ---------------------------------------------------------------------

// What a key's value may be: a number in a range, true/false, or one of a few words.
enum class KeyKind { positive, non_negative, above_one, flag, choice };

// The range of a number's kind as the messages write it ("> 0"), and whether v is in it.
constexpr std::string_view bound_of(KeyKind kind) {
  return kind == KeyKind::non_negative ? ">= 0" : kind == KeyKind::above_one ? "> 1" : "> 0";
}
constexpr bool within(KeyKind kind, double v) {
  return kind == KeyKind::non_negative ? v >= 0 : kind == KeyKind::above_one ? v > 1 : v > 0;
}

// One key of a law's scenario table. A number's default need not lie in its range: 0 may
// stand for "derived" (the pair's smaller diameter, the normal law's stiffness ratio).
struct LawKey {
  std::string_view name;     // as the scenario spells it
  KeyKind kind = KeyKind::positive;
  std::string_view meaning;  // for messages: "the spring constant k_n in N/m"
  bool required = false;
  double fallback = 0;                      // the default of a number, or of a flag (0, 1)
  std::array<std::string_view, 4> words{};  // a choice's words; the first is the default
};

namespace law_key {
constexpr LawKey required(std::string_view name, KeyKind kind, std::string_view meaning) {
  return {name, kind, meaning, true, 0, {}};
}
constexpr LawKey number(std::string_view name, KeyKind kind, double fallback, std::string_view meaning) {
  return {name, kind, meaning, false, fallback, {}};
}
constexpr LawKey flag(std::string_view name, bool fallback, std::string_view meaning) {
  return {name, KeyKind::flag, meaning, false, fallback ? 1.0 : 0.0, {}};
}
constexpr LawKey choice(std::string_view name, std::array<std::string_view, 4> words, std::string_view meaning) {
  return {name, KeyKind::choice, meaning, false, 0, words};
}
}  // namespace law_key

// The values of a pair's law keys, as read from the scenario or set by code: a number, a
// flag or a choice's word per key. Keys left out take their law's default when it is built.
class LawValues {
 public:
  using Value = std::variant<double, bool, std::string>;
  void set(std::string_view key, Value v) { values_.insert_or_assign(std::string(key), std::move(v)); }
  const Value* find(std::string_view key) const;
  double number(std::string_view key) const;  // these three throw std::invalid_argument for a key
  bool flag(std::string_view key) const;      // not set or set to another type
  const std::string& word(std::string_view key) const;
  auto begin() const { return values_.begin(); }
  auto end() const { return values_.end(); }
  bool operator==(const LawValues&) const = default;

 private:
  std::map<std::string, Value, std::less<>> values_;
};

// ---- Integrators -----------------------------------------------------------------------

// The integrators a law runs with, as simulation.integrator names them, and why not the
// others (the message's reason: "model X <why> and cannot run with ..."). A law lists the
// rules it obeys; it runs with an integrator that every one of them allows.
struct IntegratorRule {
  std::array<std::string_view, 3> allowed{};
  std::string_view why;
  constexpr bool allows(std::string_view integrator) const {
    for (std::string_view a : allowed)
      if (a == integrator) return true;
    return false;
  }
  constexpr std::size_t count() const {
    std::size_t n = 0;
    for (std::string_view a : allowed) n += !a.empty();
    return n;
  }
};
// (Every entry is written out: GCC 12 cannot read a copy of a partly defaulted array in a
// constant expression, which the law table's checks do.)
inline constexpr IntegratorRule kFixedSteps{
    {"velocity_verlet", "symplectic_euler", ""},
    "is defined on fixed time steps (its history or position correction assumes one global dt)"};
inline constexpr IntegratorRule kSymplecticEulerOnly{{"symplectic_euler", "", ""}, "is built on the symplectic Euler scheme"};

// ---- History ---------------------------------------------------------------------------

// How a history slot changes when the pair is seen from its other particle
// (world/contact_list.hpp, Contact): a property of the pair keeps, a vector in the contact
// plane is negated.
enum class Swap { keep, negate };
// A normal law's slots are ContactHistory::normal[0], [1], ... in order (they keep); a
// tangential law's one slot is the spring ContactHistory::xi (it is negated).
struct HistorySlot {
  std::string_view what;
  Swap swap = Swap::keep;
};

// ---- Building --------------------------------------------------------------------------

// Effective moduli of two materials (spec notation): E* and G*.
double effective_modulus(const Material& a, const Material& b);
double effective_shear_modulus(const Material& a, const Material& b);

// The two materials of a pair and the generic keys: what every law's builder may read.
struct MaterialPair {
  const Material& a;
  const Material& b;
  double restitution = 1;  // e
  double friction = 0;     // mu
  double effective_modulus() const { return tsubu::effective_modulus(a, b); }  // E*
  // The pair's Poisson ratio where a model needs one (slip cap, kappa, model H's tangential
  // damping): the mean of the two.
  double poisson() const { return 0.5 * (a.poisson + b.poisson); }
};

// What the loader and the law table read of a law. traits_of<Law>() gathers them from its
// struct, with the defaults of the traits it leaves out.
struct LawTraits {
  std::string_view name;                        // as the scenario spells it
  std::string_view label;                       // in messages: "hertz_tsuji (T)"
  std::span<const LawKey> keys;                 // default: none
  std::span<const IntegratorRule> integrators;  // default: any integrator
  std::span<const HistorySlot> history;         // default: none
  std::string_view default_tangential;          // a normal law's partner when the scenario names none: "mindlin"
  constexpr bool allows(std::string_view integrator) const {
    for (const IntegratorRule& r : integrators)
      if (!r.allows(integrator)) return false;
    return true;
  }
  constexpr const LawKey* key(std::string_view key_name) const {
    for (const LawKey& k : keys)
      if (k.name == key_name) return &k;
    return nullptr;
  }
};

// A builder's input: the pair, and its law's keys, each the value set or its default.
// A value out of its key's range, or a required key not set, throws std::invalid_argument
// (the loader refuses both first, with the scenario's file and line).
class LawInput : public MaterialPair {
 public:
  LawInput(const MaterialPair& pair, const LawValues& values, const LawTraits& law)
      : MaterialPair(pair), values_(values), law_(law) {}
  double number(std::string_view key) const;
  bool flag(std::string_view key) const;
  bool is(std::string_view key, std::string_view word) const;  // a choice's word

 private:
  const LawKey& key(std::string_view name, KeyKind kind) const;
  const LawValues& values_;
  LawTraits law_;
};

// What the tangential law of a pair takes from its normal law: the two models' cross-talk,
// traits of the normal law, each with its default where the law declares none.
struct NormalSide {
  // eta_t / eta_n of the tangential dashpot: `tangential_dashpot_ratio(sigma)`, else 1.
  double dashpot_ratio = 1;
  // `linear_spring`: a linear tangential spring k_t = kappa k_n takes eta_t = sqrt(kappa) eta_n,
  // the same damping ratio on both axes, instead of dashpot_ratio.
  bool linear_spring = false;
  // kappa where the scenario gives none: `tangential_stiffness_ratio(sigma)`, else
  // 2(1 - sigma)/(2 - sigma).
  double stiffness_ratio = 0;
  // `projected_spring`: the spring follows the contact plane as LIGGGHTS' does (model HH).
  bool projected_spring = false;
};

template <class Normal>
NormalSide normal_side(const Normal& n, double sigma) {
  NormalSide s;
  if constexpr (requires { n.tangential_dashpot_ratio(sigma); }) s.dashpot_ratio = n.tangential_dashpot_ratio(sigma);
  if constexpr (requires { Normal::linear_spring; }) s.linear_spring = Normal::linear_spring;
  if constexpr (requires { n.tangential_stiffness_ratio(sigma); }) s.stiffness_ratio = n.tangential_stiffness_ratio(sigma);
  else s.stiffness_ratio = 2 * (1 - sigma) / (2 - sigma);
  if constexpr (requires { Normal::projected_spring; }) s.projected_spring = Normal::projected_spring;
  return s;
}

// ---- A law's traits, whatever its type ---------------------------------------------------

namespace law_defaults {
inline constexpr std::array<LawKey, 0> keys{};
inline constexpr std::array<IntegratorRule, 0> integrators{};
inline constexpr std::array<HistorySlot, 0> history{};
}  // namespace law_defaults

template <class Law>
constexpr LawTraits traits_of() {
  LawTraits t;
  t.name = Law::name;
  if constexpr (requires { Law::label; }) t.label = Law::label;
  else t.label = Law::name;
  if constexpr (requires { Law::keys; }) t.keys = Law::keys;
  else t.keys = law_defaults::keys;
  if constexpr (requires { Law::integrators; }) t.integrators = Law::integrators;
  else t.integrators = law_defaults::integrators;
  if constexpr (requires { Law::history; }) t.history = Law::history;
  else t.history = law_defaults::history;
  if constexpr (requires { Law::default_tangential; }) t.default_tangential = Law::default_tangential;
  else t.default_tangential = "mindlin";
  return t;
}

// The traits of every law of a variant (the registry: NormalModel, TangentialModel), in its order.
template <class Variant>
constexpr auto traits_of_all() {
  return []<std::size_t... I>(std::index_sequence<I...>) {
    return std::array<LawTraits, sizeof...(I)>{traits_of<std::variant_alternative_t<I, Variant>>()...};
  }(std::make_index_sequence<std::variant_size_v<Variant>>{});
}

// The law named `name` among `laws`, or nullptr.
constexpr const LawTraits* find_law(std::span<const LawTraits> laws, std::string_view name) {
  for (const LawTraits& t : laws)
    if (t.name == name) return &t;
  return nullptr;
}

// Calls f(std::type_identity<Law>{}) for each law of a variant, in its order.
template <class Variant, class F>
void for_each_law(F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(std::type_identity<std::variant_alternative_t<I, Variant>>{}), ...);
  }(std::make_index_sequence<std::variant_size_v<Variant>>{});
}

}  // namespace tsubu
