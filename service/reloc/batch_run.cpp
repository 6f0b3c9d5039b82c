#include "reloc/batch_run.hpp"

#include <fmt/core.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <atomic>
#include <exception>
#include <filesystem>

namespace polyloc::reloc {

std::vector<TaskOutcome> runTasks(const JobContext& ctx, const Plan& plan, std::span<const size_t> mine, int jobs,
                                  int threads, int rank, ProgressBoard& progress) {
  std::vector<TaskOutcome> out(mine.size());
  std::atomic<size_t> next{0};
  auto work = [&] {  // one of `jobs` loops, each taking the next task
    for (size_t k; (k = next.fetch_add(1)) < mine.size();) {
      const Task& t = plan.tasks[mine[k]];
      TaskOutcome& o = out[k];
      o.task = mine[k];
      o.rank = rank;
      JobOptions job = t.job;
      job.progress = [&progress, k](double f, uint64_t) { progress.update(k, f); };
      job.log = [&o](const std::string& s) { o.log.push_back(s); };
      progress.start(k);
      try {
        // Isolated: a thread waiting inside this task's weighting must not pick up another
        // recording (that one would then hold this one until it ends).
        tbb::this_task_arena::isolate([&] { o.result = runRecordingJob(ctx, job); });
        o.ok = true;
      } catch (const std::exception& e) {
        o.error = e.what();
        const std::string seg = t.segments > 1 ? fmt::format(" (segment {}/{})", t.segment + 1, t.segments) : "";
        progress.message(fmt::format("polyloc relocalize: {}{} failed: {}", t.job.input, seg, o.error));
      }
      progress.finish(k);
    }
  };
  tbb::task_arena arena(threads > 0 ? threads : std::max(1, jobs));
  arena.execute([&] {
    tbb::task_group g;
    for (int j = 0; j < std::max(1, jobs); ++j) g.run(work);
    g.wait();
  });
  return out;
}

std::vector<TaskOutcome> failedTasks(std::span<const size_t> mine, int rank, const std::string& error) {
  std::vector<TaskOutcome> out;
  for (size_t t : mine) out.push_back({t, rank, false, error, {}, {}});
  return out;
}

}  // namespace polyloc::reloc
