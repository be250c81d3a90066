// The processes among which block steps share out their active particles (docs/parallel.md,
// "Block steps on several processes"): every process holds every particle and takes the same
// decisions; at each block time each evaluates and corrects its share of the active
// particles, and all exchange what they found.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace tsubu {

class ActiveShare {
 public:
  virtual ~ActiveShare() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every process's bytes, by process, on every process (valid until the next call).
  virtual std::vector<std::string_view> gather_all(const std::string& bytes) = 0;
};

}  // namespace tsubu
