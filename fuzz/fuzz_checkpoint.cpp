// libFuzzer target: the checkpoint decoder must refuse any byte string with CheckpointError
// (never crash, overrun or allocate without bound). See docs/reliability.md.
// Inputs of 32 bytes or more get a header whose size and checksum match their payload half
// of the time, so that mutations reach the parser behind the checksum.
#include <cstdint>
#include <cstring>
#include <string>

#include "tsubu/app/checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (bytes.size() >= 32 && (bytes[0] & 1) == 0) {
    bytes.replace(0, 8, "TSUBUCKP");
    const std::uint64_t n = bytes.size() - 32;
    std::uint64_t h = 1469598103934665603ULL;
    for (std::size_t k = 32; k < bytes.size(); ++k) h = (h ^ static_cast<unsigned char>(bytes[k])) * 1099511628211ULL;
    std::memcpy(bytes.data() + 16, &n, 8);
    std::memcpy(bytes.data() + 24, &h, 8);
  }
  try {
    const tsubu::Checkpoint c = tsubu::decode_checkpoint(bytes);
    if (tsubu::encode_checkpoint(c) != bytes) __builtin_trap();  // accepted input must round-trip
  } catch (const tsubu::CheckpointError&) {
  }
  return 0;
}
