// Errors that leave the engine with a defined exit code (see docs/cli.md).
#pragma once
#include <stdexcept>
#include <string>

namespace tsubu {

// Bad input: "file:line: key: what is wrong and what is allowed". Exit code 2.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, long line, const std::string& key, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + (key.empty() ? "" : key + ": ") + what) {}
};

// The simulation became unphysical (NaN, runaway overlap, particle lost). Exit code 3.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tsubu
