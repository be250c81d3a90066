// libFuzzer target: the particle CSV reader must answer any bytes with grains or an
// InputError (never crash or throw anything else). See docs/reliability.md.
#include <cstdint>
#include <sstream>
#include <string>

#include "tsubu/core/error.hpp"
#include "tsubu/source/sources.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    tsubu::parse_csv_grains(in, "fuzz.csv");
  } catch (const tsubu::InputError&) {
  }
  return 0;
}
