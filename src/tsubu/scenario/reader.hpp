// Typed, checked access to one TOML table of a scenario. Every error names the file, the
// line and the full key path; keys that were never asked for are reported as unknown, with
// the closest allowed key as a suggestion.
#pragma once
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "tsubu/core/error.hpp"
#include "tsubu/core/vec3.hpp"

namespace tsubu {

class Section {
 public:
  Section(const toml::table& table, std::string path, std::string file);

  const std::string& path() const { return path_; }
  long line() const;
  long line_of(std::string_view key) const;
  bool has(std::string_view key) const;
  std::string key_path(std::string_view key) const;

  [[noreturn]] void fail(std::string_view key, const std::string& what) const;
  // Where a key's value came from: its line, or the --set that gave it; for an absent key, the
  // table's (the --set that gave the table, or its line). where() is the table's own.
  SourceLocation where(std::string_view key) const;
  SourceLocation where() const;
  std::vector<SourceLocation> key_locations() const;  // where() of every key the table holds

  double real(std::string_view key);  // required
  double real(std::string_view key, double fallback);
  double positive(std::string_view key);  // required, > 0
  double positive(std::string_view key, double fallback);
  std::int64_t integer(std::string_view key, std::int64_t fallback);
  bool flag(std::string_view key, bool fallback);
  std::string text(std::string_view key);  // required
  std::string text(std::string_view key, const std::string& fallback);
  std::string choice(std::string_view key, std::initializer_list<const char*> allowed, std::optional<std::string> fallback);
  std::string choice(std::string_view key, std::span<const std::string_view> allowed, std::optional<std::string> fallback);
  Vec3 vec3(std::string_view key);
  Vec3 vec3(std::string_view key, const Vec3& fallback);
  std::vector<double> reals(std::string_view key);  // array of numbers
  std::vector<std::string> texts(std::string_view key, std::vector<std::string> fallback);
  std::vector<std::int64_t> integers(std::string_view key, std::vector<std::int64_t> fallback);

  std::optional<Section> table(std::string_view key);
  std::vector<Section> tables(std::string_view key);  // array of tables (may be absent)

  // Reports the first key of the table that no accessor asked for. Call after reading.
  void finish(std::initializer_list<const char*> also_allowed = {}) const;

 private:
  const toml::table* table_;
  std::string path_, file_;
  mutable std::set<std::string, std::less<>> asked_;  // every key looked up, present or not

  const toml::node& node(std::string_view key);  // marks used; requires presence
  std::vector<double> numbers(std::string_view key, std::size_t expected);
  template <class T>
  std::vector<T> array_of(std::string_view key, std::vector<T> fallback, const char* what);
};

// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);

}  // namespace tsubu
