// The probe of the LawLoopVectorises test (tests/vectorisation/law_loop.cmake): one contact law's
// loop over a block of pairs, compiled alone, so that the compiler's vectoriser report names
// no other loop. PROBE_NORMAL, PROBE_TANGENTIAL and PROBE_ROLLING name the law; PROBE_NUMBER
// its number type.
#include "tsubu/forces/evaluate.hpp"

namespace tsubu {

void law_loop_probe(Lanes<ForceField::kBlock, PROBE_NUMBER>& lanes, std::size_t m, const PROBE_NORMAL& normal,
                    const PROBE_TANGENTIAL& tangential, const PROBE_ROLLING& rolling) {
  lanes.evaluate_all(m, normal, tangential, rolling);
}

}  // namespace tsubu
