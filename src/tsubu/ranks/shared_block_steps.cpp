#include "tsubu/ranks/shared_block_steps.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace tsubu {

namespace {

class ProcessShare final : public ActiveShare {
 public:
  explicit ProcessShare(const Communicator& comm) : comm_(comm) {}
  int rank() const override { return comm_.rank(); }
  int size() const override { return comm_.size(); }
  std::vector<std::string_view> gather_all(const std::string& bytes) override { return comm_.gather_all(bytes, received_); }

 private:
  const Communicator& comm_;
  std::string received_;
};

}  // namespace

std::unique_ptr<ActiveShare> share_block_steps(const Communicator& comm, Simulation& sim) {
  auto share = std::make_unique<ProcessShare>(comm);
  sim.block()->share_among(share.get());
  return share;
}

}  // namespace tsubu
