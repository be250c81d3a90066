// Block steps on several processes (docs/parallel.md, "Block steps on several processes"):
// every process holds the whole run, and at each block time evaluates and corrects its share
// of the active particles (BlockHermite::share_among); MPI's processes exchange what they found.
#pragma once
#include <memory>

#include "tsubu/integrate/active_share.hpp"
#include "tsubu/ranks/communicator.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu {

// Shares the block steps of `sim` (which must have them) among comm's processes; the share
// returned must outlive sim's stepping.
std::unique_ptr<ActiveShare> share_block_steps(const Communicator& comm, Simulation& sim);

}  // namespace tsubu
