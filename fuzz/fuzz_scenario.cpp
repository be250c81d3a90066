// libFuzzer target: the scenario loader must answer any text with a Scenario or an
// InputError (never crash or throw anything else). CSV files are not opened
// (particle_files = false). See docs/reliability.md.
#include <cstdint>
#include <string>

#include "tsubu/core/error.hpp"
#include "tsubu/scenario/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    tsubu::load_scenario_text(text, "fuzz.toml", {}, false);
  } catch (const tsubu::InputError&) {
  }
  return 0;
}
