// Runs this process's tasks of a relocalisation plan with TBB: one arena of `threads` threads
// in which `jobs` tasks run side by side, each weighing its particles in the same arena
// (docs/relocalize.md, "TBB jobs"). A task that throws becomes a failed outcome; the others go
// on. Results do not depend on jobs or threads: random numbers are counter-based.
#pragma once

#include "reloc/batch_plan.hpp"
#include "reloc/outcome.hpp"
#include "reloc/progress_board.hpp"

#include <span>
#include <vector>

namespace polyloc::reloc {

// ctx.config.mcl.threads must be 0 and the caster must run in the caller's arena (EmbreeOptions
// threads < 0), or the weighting leaves this arena. Outcomes in the order of `mine`.
std::vector<TaskOutcome> runTasks(const JobContext& ctx, const Plan& plan, std::span<const size_t> mine, int jobs,
                                  int threads, int rank, ProgressBoard& progress);

// Every task of `mine` failed with `error` (e.g. the map did not load on this rank).
std::vector<TaskOutcome> failedTasks(std::span<const size_t> mine, int rank, const std::string& error);

}  // namespace polyloc::reloc
