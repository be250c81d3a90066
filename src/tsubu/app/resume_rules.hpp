// What a resume may change, and what it must not lose (docs/reliability.md).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/scenario/scenario.hpp"

namespace tsubu {

// The run's scenario with the resume's --set values ("key=value") appended to its overrides,
// the run being at step `step`. Only the duration and the output and checkpoint intervals
// may change (none changes a step already taken or an output already written): any other
// key throws InputError, and so does a duration that ends before `step`. Output intervals
// that follow from the duration (unset in the scenario) keep the run's values unless set:
// pinned by overrides of their own, so that later resumes keep them too.
Scenario with_resume_overrides(const Scenario& run, const std::vector<std::string>& sets, std::int64_t step);

// A resume continues the outputs from their length at checkpoint c (read from `used`) and
// ends at the end of the run `sc` (as the checkpoint and the --sets give it): rows past that
// end, which a session that left no checkpoint of its end may have written, would be deleted
// and not written again. Throws UsageError naming them and the --set that keeps them, before
// anything is touched.
void refuse_losing_rows(const Scenario& sc, const Checkpoint& c, const std::filesystem::path& used,
                        const std::string& out_dir);

}  // namespace tsubu
