// FNV-1a, 64 bits: the scenario's hash (Scenario::hash) and the checkpoints' checksum.
#pragma once
#include <cstdint>
#include <string_view>

namespace tsubu {

constexpr std::uint64_t kFnv1aStart = 1469598103934665603ULL;

// The hash of `bytes`, continuing from h (kFnv1aStart for a new hash).
inline std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = kFnv1aStart) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

}  // namespace tsubu
