#include "tsubu/scenario/reader.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tsubu/core/error.hpp"

namespace tsubu {

namespace {

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date/time";
  }
}

// The file a node came from: a value given on the command line (--set) carries its own name.
const std::string& origin(const toml::node* n, const std::string& file) {
  const auto& src = n ? n->source().path : nullptr;
  return src && !src->empty() ? *src : file;
}

std::optional<double> as_number(const toml::node& n) {
  if (auto v = n.value_exact<double>()) return *v;
  if (auto v = n.value_exact<std::int64_t>()) return static_cast<double>(*v);
  return std::nullopt;
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

Section::Section(const toml::table& table, std::string path, std::string file)
    : table_(&table), path_(std::move(path)), file_(std::move(file)) {}

long Section::line() const { return static_cast<long>(table_->source().begin.line); }

long Section::line_of(std::string_view key) const {
  if (const toml::node* n = table_->get(key)) return static_cast<long>(n->source().begin.line);
  return line();
}

bool Section::has(std::string_view key) const {
  asked_.insert(std::string(key));
  return table_->contains(key);
}

std::string Section::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

SourceLocation Section::where(std::string_view key) const {
  const toml::node* n = table_->get(key);
  return {origin(n ? n : table_, file_), line_of(key), key_path(key)};
}

SourceLocation Section::where() const { return {origin(table_, file_), line(), path_}; }

std::vector<SourceLocation> Section::key_locations() const {
  std::vector<SourceLocation> out;
  for (const auto& [k, v] : *table_) out.push_back(where(k.str()));
  return out;
}

void Section::fail(std::string_view key, const std::string& what) const {
  std::string hint;  // a missing key may be a misspelt one
  if (!table_->contains(key))
    for (const auto& [k, v] : *table_)
      if (!asked_.count(k.str()) && edit_distance(k.str(), key) < 3)
        hint = " (line " + std::to_string(v.source().begin.line) + " has '" + std::string(k.str()) + "': a typo?)";
  throw InputError(where(key), what + hint);
}

const toml::node& Section::node(std::string_view key) {
  asked_.insert(std::string(key));
  const toml::node* n = table_->get(key);
  if (!n) fail(key, "is required but missing");
  return *n;
}

double Section::real(std::string_view key) {
  const toml::node& n = node(key);
  auto v = as_number(n);
  if (!v && n.is_string()) fail(key, "must be a number, got the string \"" + *n.value<std::string>() + "\" (write numbers without quotes)");
  if (!v) fail(key, std::string("must be a number, got ") + type_name(n));
  if (!std::isfinite(*v)) fail(key, "must be a finite number");
  return *v;
}

double Section::real(std::string_view key, double fallback) { return has(key) ? real(key) : fallback; }

double Section::positive(std::string_view key) {
  const double v = real(key);
  if (!(v > 0)) {
    std::ostringstream s;
    s << "must be > 0, got " << v;
    fail(key, s.str());
  }
  return v;
}

double Section::positive(std::string_view key, double fallback) { return has(key) ? positive(key) : fallback; }

std::int64_t Section::integer(std::string_view key, std::int64_t fallback) {
  if (!has(key)) return fallback;
  const toml::node& n = node(key);
  auto v = n.value_exact<std::int64_t>();
  if (!v) fail(key, std::string("must be an integer, got ") + type_name(n));
  return *v;
}

bool Section::flag(std::string_view key, bool fallback) {
  if (!has(key)) return fallback;
  const toml::node& n = node(key);
  auto v = n.value_exact<bool>();
  if (!v) fail(key, std::string("must be true or false, got ") + type_name(n));
  return *v;
}

std::string Section::text(std::string_view key) {
  const toml::node& n = node(key);
  auto v = n.value_exact<std::string>();
  if (!v) fail(key, std::string("must be a string, got ") + type_name(n));
  return *v;
}

std::string Section::text(std::string_view key, const std::string& fallback) { return has(key) ? text(key) : fallback; }

std::string Section::choice(std::string_view key, std::initializer_list<const char*> allowed,
                            std::optional<std::string> fallback) {
  const std::vector<std::string_view> words(allowed.begin(), allowed.end());
  return choice(key, std::span<const std::string_view>(words), std::move(fallback));
}

std::string Section::choice(std::string_view key, std::span<const std::string_view> allowed,
                            std::optional<std::string> fallback) {
  if (!has(key) && fallback) return *fallback;
  const std::string v = text(key);
  for (std::string_view a : allowed)
    if (v == a) return v;
  std::string list;
  for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string("\"") + std::string(a) + "\"";
  fail(key, "\"" + v + "\" is not allowed; allowed: " + list);
}

std::vector<double> Section::numbers(std::string_view key, std::size_t expected) {
  const toml::node& n = node(key);
  const toml::array* arr = n.as_array();
  if (!arr) fail(key, std::string("must be an array of numbers, got ") + type_name(n));
  std::vector<double> out;
  for (const auto& e : *arr) {
    auto v = as_number(e);
    if (!v || !std::isfinite(*v)) fail(key, "must be an array of finite numbers");
    out.push_back(*v);
  }
  if (expected && out.size() != expected)
    fail(key, "must have " + std::to_string(expected) + " numbers, got " + std::to_string(out.size()));
  return out;
}

Vec3 Section::vec3(std::string_view key) {
  const auto v = numbers(key, 3);
  return {v[0], v[1], v[2]};
}

Vec3 Section::vec3(std::string_view key, const Vec3& fallback) { return has(key) ? vec3(key) : fallback; }

std::vector<double> Section::reals(std::string_view key) { return numbers(key, 0); }

template <class T>
std::vector<T> Section::array_of(std::string_view key, std::vector<T> fallback, const char* what) {
  if (!has(key)) return fallback;
  const toml::node& n = node(key);
  const toml::array* arr = n.as_array();
  if (!arr) fail(key, std::string("must be an array of ") + what + ", got " + type_name(n));
  std::vector<T> out;
  for (const auto& e : *arr) {
    auto v = e.template value_exact<T>();
    if (!v) fail(key, std::string("must be an array of ") + what);
    out.push_back(*v);
  }
  return out;
}

std::vector<std::string> Section::texts(std::string_view key, std::vector<std::string> fallback) {
  return array_of(key, std::move(fallback), "strings");
}

std::vector<std::int64_t> Section::integers(std::string_view key, std::vector<std::int64_t> fallback) {
  return array_of(key, std::move(fallback), "integers");
}

std::optional<Section> Section::table(std::string_view key) {
  if (!has(key)) return std::nullopt;
  const toml::node& n = node(key);
  const toml::table* t = n.as_table();
  if (!t) fail(key, std::string("must be a table, got ") + type_name(n));
  return Section(*t, key_path(key), file_);
}

std::vector<Section> Section::tables(std::string_view key) {
  std::vector<Section> out;
  if (!has(key)) return out;
  const toml::node& n = node(key);
  const toml::array* arr = n.as_array();
  if (!arr || !arr->is_array_of_tables())
    fail(key, std::string("must be an array of tables ([[") + key_path(key) + "]]), got " + type_name(n));
  for (std::size_t k = 0; k < arr->size(); ++k)
    out.emplace_back(*arr->get(k)->as_table(), key_path(key) + "[" + std::to_string(k) + "]", file_);
  return out;
}

void Section::finish(std::initializer_list<const char*> also_allowed) const {
  for (const auto& [k, v] : *table_) {
    const std::string key(k.str());
    if (asked_.count(key)) continue;
    if (std::any_of(also_allowed.begin(), also_allowed.end(), [&](const char* a) { return key == a; })) continue;
    std::string best;
    std::size_t best_d = 3;  // suggest only close matches
    std::string allowed;
    std::vector<std::string> names(asked_.begin(), asked_.end());
    for (const char* a : also_allowed) names.emplace_back(a);
    for (const auto& a : names) {
      allowed += (allowed.empty() ? "" : ", ") + a;
      const std::size_t d = edit_distance(key, a);
      if (d < best_d) best_d = d, best = a;
    }
    throw InputError(origin(&v, file_), static_cast<long>(v.source().begin.line), key_path(key),
                     "unknown key" + (best.empty() ? std::string() : " (did you mean '" + best + "'?)") +
                         (allowed.empty() ? std::string() : "; allowed here: " + allowed));
  }
}

}  // namespace tsubu
