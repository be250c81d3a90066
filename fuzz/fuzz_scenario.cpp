// libFuzzer target: the scenario loader must answer any text with a Scenario or an
// InputError (never crash or throw anything else). Lines starting with "--set " are taken
// as --set overrides (the rest of the line), so the override path is fuzzed too. CSV files
// are not opened (particle_files = false). See docs/reliability.md.
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "tsubu/core/error.hpp"
#include "tsubu/scenario/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::string text;
  std::vector<std::string> overrides;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("--set ", 0) == 0) overrides.push_back(line.substr(6));
    else text += line + "\n";
  }
  try {
    tsubu::load_scenario_text(text, "fuzz.toml", overrides, false);
  } catch (const tsubu::InputError&) {
  }
  return 0;
}
