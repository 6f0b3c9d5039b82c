// Rank 0 (or the only process) of `polyloc relocalize`: merges the outcomes of all tasks into
// the outputs (docs/relocalize.md, "Outputs"): per input DIR/<name>/trajectory.tum, frames.csv,
// plot.png, summary.json; over all inputs DIR/summary.json, which lists what failed or is missing.
#pragma once

#include "reloc/batch_plan.hpp"
#include "reloc/outcome.hpp"

#include <nlohmann/json.hpp>
#include <vector>

namespace polyloc::reloc {

// Segments of one recording, in segment order, into one result: frames and ground truth in
// time order, counters and times summed, the start of the first segment.
JobResult mergeSegments(std::vector<JobResult> parts);

// Writes every output; returns the summary (also DIR/summary.json). "all_succeeded" says
// whether every input ran whole. `context` adds keys (jobs, ranks, wall_s) to the summary.
nlohmann::json writeBatch(const Mesh& mesh, const BatchOptions& options, const Plan& plan,
                          std::vector<TaskOutcome> outcomes, const nlohmann::json& context);

}  // namespace polyloc::reloc
