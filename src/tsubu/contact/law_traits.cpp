#include "tsubu/contact/law_traits.hpp"

#include <algorithm>
#include <stdexcept>

#include "tsubu/core/format.hpp"

namespace tsubu {

double effective_modulus(const Material& a, const Material& b) {
  return 1.0 / ((1 - a.poisson * a.poisson) / a.youngs_modulus + (1 - b.poisson * b.poisson) / b.youngs_modulus);
}

double effective_shear_modulus(const Material& a, const Material& b) {
  auto term = [](const Material& m) { return 2 * (2 - m.poisson) * (1 + m.poisson) / m.youngs_modulus; };
  return 1.0 / (term(a) + term(b));
}

namespace {

template <class T>
const T& value_as(const LawValues& values, std::string_view key, const char* what) {
  const LawValues::Value* v = values.find(key);
  if (!v || !std::holds_alternative<T>(*v))
    throw std::invalid_argument("law key " + std::string(key) + (v ? " is not " : " is not set: expected ") + what);
  return std::get<T>(*v);
}

}  // namespace

const LawValues::Value* LawValues::find(std::string_view key) const {
  const auto it = values_.find(key);
  return it == values_.end() ? nullptr : &it->second;
}

double LawValues::number(std::string_view key) const { return value_as<double>(*this, key, "a number"); }
bool LawValues::flag(std::string_view key) const { return value_as<bool>(*this, key, "true or false"); }
const std::string& LawValues::word(std::string_view key) const { return value_as<std::string>(*this, key, "a word"); }

const LawKey& LawInput::key(std::string_view name, KeyKind kind) const {
  const LawKey* k = law_.key(name);
  const bool number = kind != KeyKind::flag && kind != KeyKind::choice;
  if (!k || (number ? k->kind == KeyKind::flag || k->kind == KeyKind::choice : k->kind != kind))
    throw std::logic_error(std::string(law_.name) + " declares no such key: " + std::string(name));
  return *k;
}

double LawInput::number(std::string_view name) const {
  const LawKey& k = key(name, KeyKind::positive);
  if (!values_.find(name)) {
    if (k.required) throw std::invalid_argument(std::string(law_.name) + " needs " + std::string(name) + ": " + std::string(k.meaning));
    return k.fallback;
  }
  const double v = values_.number(name);
  if (!within(k.kind, v))
    throw std::invalid_argument(std::string(law_.name) + ": " + std::string(name) + " must be " + std::string(bound_of(k.kind)) +
                                ", got " + format_number(v));
  return v;
}

bool LawInput::flag(std::string_view name) const {
  const LawKey& k = key(name, KeyKind::flag);
  return values_.find(name) ? values_.flag(name) : k.fallback != 0;
}

bool LawInput::is(std::string_view name, std::string_view word) const {
  const LawKey& k = key(name, KeyKind::choice);
  auto among = [&](std::string_view w) { return !w.empty() && std::find(k.words.begin(), k.words.end(), w) != k.words.end(); };
  if (!among(word)) throw std::logic_error(std::string(law_.name) + ": " + std::string(name) + " has no word " + std::string(word));
  const std::string_view given = values_.find(name) ? std::string_view(values_.word(name)) : k.words[0];
  if (!among(given))
    throw std::invalid_argument(std::string(law_.name) + ": " + std::string(name) + " = \"" + std::string(given) + "\" is not one of its words");
  return given == word;
}

}  // namespace tsubu
