#include "tsubu/scenario/law_keys.hpp"

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "tsubu/core/format.hpp"
#include "tsubu/integrate/integrators.hpp"

namespace tsubu {

namespace {

std::string quoted(std::string_view word) {
  std::string out = "\"";
  out.append(word);
  return out += '"';
}

// "\"a\", \"b\", \"c\"" with `last` (", " or " or ") before the last word.
std::string listed(const std::vector<std::string_view>& words, std::string_view last) {
  std::string out;
  for (std::size_t k = 0; k < words.size(); ++k)
    out += std::string(k == 0 ? "" : k + 1 == words.size() ? last : ", ") + quoted(words[k]);
  return out;
}

std::vector<std::string_view> names_of(std::span<const LawTraits> laws) {
  std::vector<std::string_view> names;
  for (const LawTraits& law : laws) names.push_back(law.name);
  return names;
}

// The law `role` names (the default where the table leaves it out and the registry has it).
const LawTraits& chosen_law(Section& s, std::string_view role, std::span<const LawTraits> laws, std::string_view fallback) {
  const std::optional<std::string> default_name = find_law(laws, fallback) ? std::optional<std::string>(fallback) : std::nullopt;
  const std::vector<std::string_view> names = names_of(laws);
  return *find_law(laws, s.choice(role, std::span<const std::string_view>(names), default_name));
}

// Every integrator a law's traits name is one simulation.integrator knows: a misspelt name
// in a rule would otherwise refuse that integrator for the law without a word.
constexpr bool names_integrators(std::span<const LawTraits> laws) {
  for (const LawTraits& law : laws)
    for (const IntegratorRule& rule : law.integrators)
      for (std::string_view name : rule.allowed) {
        bool known = name.empty();
        for (Integrator i : kIntegrators) known = known || name == integrator_name(i);
        if (!known) return false;
      }
  return true;
}
static_assert(names_integrators(kNormalLaws) && names_integrators(kTangentialLaws) && names_integrators(kRollingLaws),
              "a law's IntegratorRule names an integrator that integrator_name() does not give");

// Refuses an integrator the law does not allow, with the reason of its first rule that
// refuses it: what it needs where the rule allows one integrator, else the laws of `laws`
// that run with this one.
void check_integrator(Section& s, std::string_view role, const LawTraits& law, std::string_view integrator,
                      std::span<const LawTraits> laws) {
  for (const IntegratorRule& rule : law.integrators) {
    if (rule.allows(integrator)) continue;
    const std::string what = "model " + quoted(law.name) + " " + std::string(rule.why);
    if (rule.count() == 1) s.fail(role, what + " and needs simulation.integrator = " + quoted(rule.allowed[0]));
    std::vector<std::string_view> allowed;
    for (const LawTraits& other : laws)
      if (other.allows(integrator)) allowed.push_back(other.name);
    s.fail(role, what + " and cannot run with simulation.integrator = " + quoted(integrator) + "; allowed with it: " +
                     listed(allowed, ", "));
  }
}

// A registry of laws and the key that chooses among them ("normal", "tangential", "rolling").
struct Registry {
  std::string_view role;
  std::span<const LawTraits> laws;
};

// Refuses the keys of the laws that the entry did not choose (`chosen`, one per registry):
// "is used only with normal = ...".
void refuse_keys_of_other_laws(Section& s, std::initializer_list<const LawTraits*> chosen,
                               std::initializer_list<Registry> registries) {
  auto users = [&](std::string_view key) {
    std::string out;
    for (const Registry& r : registries) {
      std::vector<std::string_view> names;
      for (const LawTraits& law : r.laws)
        if (law.key(key)) names.push_back(law.name);
      if (!names.empty()) out += (out.empty() ? "" : " or ") + std::string(r.role) + " = " + listed(names, " or ");
    }
    return out;
  };
  auto chosen_key = [&](std::string_view key) {
    for (const LawTraits* law : chosen)
      if (law->key(key)) return true;
    return false;
  };
  for (const Registry& r : registries)
    for (const LawTraits& law : r.laws)
      for (const LawKey& k : law.keys)
        if (!chosen_key(k.name) && s.has(k.name)) s.fail(k.name, "is used only with " + users(k.name));
}

}  // namespace

LawValues read_law_keys(Section& s, const LawTraits& law, std::string_view role) {
  LawValues values;
  for (const LawKey& k : law.keys) {
    if (!s.has(k.name)) {
      if (k.required)
        s.fail(k.name, "is required with " + std::string(role) + " = " + quoted(law.name) + ": " + std::string(k.meaning) +
                           ", a number " + std::string(bound_of(k.kind)));
    } else if (k.kind == KeyKind::flag) {
      values.set(k.name, s.flag(k.name, false));
    } else if (k.kind == KeyKind::choice) {
      std::vector<std::string_view> words;
      for (std::string_view w : k.words)
        if (!w.empty()) words.push_back(w);
      values.set(k.name, s.choice(k.name, std::span<const std::string_view>(words), std::nullopt));
    } else {
      const double v = s.real(k.name);
      if (!within(k.kind, v))
        s.fail(k.name, "is " + std::string(k.meaning) + " and must be " + std::string(bound_of(k.kind)) + ", got " + format_number(v));
      values.set(k.name, v);
    }
  }
  return values;
}

ContactSpec read_contact_spec(Section& s, std::string_view integrator, std::span<const LawTraits> normals,
                              std::span<const LawTraits> tangentials) {
  ContactSpec c;
  const LawTraits& normal = chosen_law(s, "normal", normals, c.normal);
  check_integrator(s, "normal", normal, integrator, normals);
  const LawTraits& tangential = chosen_law(s, "tangential", tangentials, normal.default_tangential);
  check_integrator(s, "tangential", tangential, integrator, tangentials);
  const LawTraits& rolling = chosen_law(s, "rolling", kRollingLaws, c.rolling);
  check_integrator(s, "rolling", rolling, integrator, kRollingLaws);
  c.normal = normal.name;
  c.tangential = tangential.name;
  c.rolling = rolling.name;
  c.restitution = s.real("restitution", 1.0);
  if (!(c.restitution > 0 && c.restitution <= 1)) s.fail("restitution", "allowed range (0, 1], got " + format_number(c.restitution));
  c.friction = s.real("friction", 0.0);
  if (c.friction < 0) s.fail("friction", "must be >= 0, got " + format_number(c.friction));
  c.values = read_law_keys(s, normal, "normal");
  for (const auto& [key, value] : read_law_keys(s, tangential, "tangential")) c.values.set(key, value);
  for (const auto& [key, value] : read_law_keys(s, rolling, "rolling")) c.values.set(key, value);
  refuse_keys_of_other_laws(s, {&normal, &tangential, &rolling},
                            {{"normal", normals}, {"tangential", tangentials}, {"rolling", kRollingLaws}});
  return c;
}

}  // namespace tsubu
