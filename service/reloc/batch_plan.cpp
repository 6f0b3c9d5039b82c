#include "reloc/batch_plan.hpp"

#include <polyloc/io/recording.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <numeric>
#include <set>

namespace polyloc::reloc {
namespace {

// a.mcap -> a; bag/metadata.yaml and bag/ -> bag; repeated names get -2, -3 ...
std::string folderName(const std::string& input, std::set<std::string>& taken) {
  std::filesystem::path p(input);
  if (p.filename().empty()) p = p.parent_path();
  std::string name = p.stem().string();
  if (name == "metadata" || p.extension() == ".db3") name = p.parent_path().filename().string();
  if (name.empty()) name = "input";
  std::string unique = name;
  for (int k = 2; !taken.insert(unique).second; ++k) unique = name + "-" + std::to_string(k);
  return unique;
}

}  // namespace

Plan planBatch(const BatchOptions& o) {
  Plan plan;
  std::set<std::string> taken;
  for (size_t i = 0; i < o.inputs.size(); ++i) {
    plan.names.push_back(folderName(o.inputs[i], taken));
    plan.input_errors.emplace_back();
    JobOptions job = o.base;
    job.input = o.inputs[i];
    job.start = o.global ? StartMode::Global : StartMode::Auto;
    if (o.segment_s <= 0) {
      std::error_code ec;  // the order of work only: by file size (a bag directory: 0)
      const auto bytes = std::filesystem::is_regular_file(o.inputs[i], ec) ? std::filesystem::file_size(o.inputs[i], ec) : 0;
      plan.tasks.push_back({i, 0, 1, ec ? 0.0 : double(bytes), job});
      continue;
    }
    RecordingSpan span;
    try {
      span = spanOf(openJobRecording(job)->topics());
    } catch (const std::exception& e) {
      plan.input_errors.back() = e.what();
      continue;
    }
    const double len_s = double(span.last_ns - span.first_ns) * 1e-9;
    const size_t n = std::max<size_t>(1, size_t(std::ceil(len_s / o.segment_s - 1e-9)));
    const auto seg_ns = int64_t(o.segment_s * 1e9), warm_ns = int64_t(o.warmup_s * 1e9);
    for (size_t k = 0; k < n; ++k) {
      JobOptions s = job;
      if (k > 0) {  // the first segment starts as a whole recording would
        s.keep_from_ns = span.first_ns + int64_t(k) * seg_ns;
        s.read_from_ns = s.keep_from_ns - warm_ns;
      }
      if (k + 1 < n) s.keep_to_ns = span.first_ns + int64_t(k + 1) * seg_ns;
      const double read_s = std::min(len_s, double(k + 1) * o.segment_s) - std::max(0.0, double(k) * o.segment_s - (k ? o.warmup_s : 0));
      plan.tasks.push_back({i, k, n, read_s, s});
    }
  }
  return plan;
}

std::vector<size_t> assignTasks(const Plan& plan, int rank, int ranks) {
  std::vector<size_t> order(plan.tasks.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return plan.tasks[a].weight > plan.tasks[b].weight; });
  std::vector<size_t> mine;
  for (size_t k = 0; k < order.size(); ++k)
    if (int(k % size_t(std::max(1, ranks))) == rank) mine.push_back(order[k]);
  return mine;
}

}  // namespace polyloc::reloc
