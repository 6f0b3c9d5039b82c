#include "reloc/batch_merge.hpp"

#include "reloc/report.hpp"

#include <polyloc/io/atomic_file.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace polyloc::reloc {

JobResult mergeSegments(std::vector<JobResult> parts) {
  if (parts.empty()) return {};
  JobResult m = std::move(parts.front());
  for (size_t i = 1; i < parts.size(); ++i) {
    JobResult& p = parts[i];
    m.frames.insert(m.frames.end(), p.frames.begin(), p.frames.end());
    m.truth.insert(m.truth.end(), p.truth.begin(), p.truth.end());
    for (const auto& [k, v] : p.counters) m.counters[k] += v;
    m.updates += p.updates;
    m.filter_s += p.filter_s;
    m.wall_s += p.wall_s;
    m.final_particles = p.final_particles, m.final_status = p.final_status, m.final_pose = p.final_pose;
    m.keep_to_ns = p.keep_to_ns;
    m.plot.estimate_path.insert(m.plot.estimate_path.end(), p.plot.estimate_path.begin(), p.plot.estimate_path.end());
    m.plot.clouds.insert(m.plot.clouds.end(), p.plot.clouds.begin(), p.plot.clouds.end());
    m.warnings.insert(m.warnings.end(), p.warnings.begin(), p.warnings.end());
  }
  auto by_stamp = [](const auto& a, const auto& b) { return a.stamp_ns < b.stamp_ns; };
  std::stable_sort(m.frames.begin(), m.frames.end(), by_stamp);
  // Warm-ups overlap: the same ground-truth pose comes from two segments.
  std::stable_sort(m.truth.begin(), m.truth.end(), by_stamp);
  m.truth.erase(std::unique(m.truth.begin(), m.truth.end(), [](const auto& a, const auto& b) { return a.stamp_ns == b.stamp_ns; }),
                m.truth.end());
  if (m.plot.clouds.size() > 4) {  // four of them, spread, the last one included
    std::vector<viz::LocalizePlotData::Cloud> keep;
    const size_t n = m.plot.clouds.size();
    for (size_t k = 0; k < 4; ++k) keep.push_back(std::move(m.plot.clouds[k * (n - 1) / 3]));
    m.plot.clouds = std::move(keep);
  }
  return m;
}

namespace {

void writeJson(const std::filesystem::path& path, const nlohmann::json& j) {
  AtomicFile file(path.string());
  std::ofstream f(file.tmp());
  f << j.dump(2) << "\n";
  f.close();
  if (!f) throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
  file.commit();
}

}  // namespace

nlohmann::json writeBatch(const Mesh& mesh, const BatchOptions& o, const Plan& plan, std::vector<TaskOutcome> outcomes,
                          const nlohmann::json& context) {
  const std::filesystem::path dir(o.out_dir);
  std::filesystem::create_directories(dir);
  std::sort(outcomes.begin(), outcomes.end(), [](const auto& a, const auto& b) { return a.task < b.task; });
  nlohmann::json inputs = nlohmann::json::array(), missing = nlohmann::json::array();
  std::vector<FrameError> pooled;
  size_t ok_inputs = 0;
  for (size_t i = 0; i < o.inputs.size(); ++i) {
    nlohmann::json entry = {{"input", o.inputs[i]}, {"name", plan.names[i]}};
    if (!plan.input_errors[i].empty()) {
      entry["status"] = "failed";
      entry["error"] = plan.input_errors[i];
      missing.push_back({{"input", o.inputs[i]}, {"segment", nullptr}, {"error", plan.input_errors[i]}});
      inputs.push_back(entry);
      continue;
    }
    std::vector<JobResult> parts;
    nlohmann::json errors = nlohmann::json::array(), ranks = nlohmann::json::array();
    size_t segments = 0;
    for (auto& oc : outcomes) {
      const Task& t = plan.tasks[oc.task];
      if (t.input != i) continue;
      segments = t.segments;
      ranks.push_back(oc.rank);
      if (oc.ok) { parts.push_back(std::move(oc.result)); continue; }
      nlohmann::json miss = {{"input", o.inputs[i]}, {"segment", t.segment}, {"rank", oc.rank}, {"error", oc.error}};
      if (t.segments > 1)
        miss["span_s"] = {t.segment * o.segment_s, t.segment + 1 < t.segments ? (t.segment + 1) * o.segment_s : -1.0};
      errors.push_back(miss);
      missing.push_back(miss);
    }
    entry["segments"] = segments;
    entry["ranks"] = ranks;
    if (parts.empty()) {
      entry["status"] = "failed";
      entry["errors"] = errors;
      inputs.push_back(entry);
      continue;
    }
    const JobResult r = mergeSegments(std::move(parts));
    const auto metrics = evaluate(r);
    const TrajectoryMetrics* mp = metrics ? &*metrics : nullptr;
    const std::filesystem::path sub = dir / plan.names[i];
    std::filesystem::create_directories(sub);
    writeTum((sub / "trajectory.tum").string(), r.frames);
    writeCsv((sub / "frames.csv").string(), mp, r.frames, o.covariance);
    const std::string cmd = segments > 1 ? fmt::format("polyloc relocalize, {} segments:", segments) : "polyloc relocalize";
    drawPlot(mesh, r, mp, (sub / "plot.png").string(), cmd);
    nlohmann::json s = resultJson(r, mp);
    s["name"] = plan.names[i];
    s["status"] = errors.empty() ? "ok" : "partial";
    s["segments"] = segments;
    s["ranks"] = ranks;
    if (!errors.empty()) s["missing"] = errors;
    if (metrics) s["ground_truth"] = r.truth_from_stream ? "/ground_truth" : "file";
    writeJson(sub / "summary.json", s);
    if (metrics) pooled.insert(pooled.end(), metrics->frames.begin(), metrics->frames.end());
    ok_inputs += errors.empty();
    s.erase("counters");
    inputs.push_back(s);
  }
  nlohmann::json summary = context;
  summary["inputs"] = inputs;
  summary["succeeded"] = ok_inputs;
  summary["failed"] = o.inputs.size() - ok_inputs;
  summary["missing"] = missing;
  summary["all_succeeded"] = ok_inputs == o.inputs.size();
  summary["segment_s"] = o.segment_s;
  summary["warmup_s"] = o.segment_s > 0 ? o.warmup_s : 0.0;
  summary["global"] = o.global;
  if (!pooled.empty()) summary["accuracy"] = summaryJson(summarize(pooled));  // every evaluated frame of every input
  writeJson(dir / "summary.json", summary);
  return summary;
}

}  // namespace polyloc::reloc
