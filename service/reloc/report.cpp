#include "reloc/report.hpp"

#include <polyloc/geometry/domain.hpp>
#include <polyloc/io/atomic_file.hpp>
#include <polyloc/eval/stats.hpp>
#include <polyloc/io/tum.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace polyloc::reloc {

nlohmann::json num(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json summaryJson(const ErrorSummary& s) {
  return {{"frames", s.frames},
          {"ate_rmse_m", num(s.ate_rmse_m)},
          {"mean_pos_err_m", num(s.mean_pos_err_m)},
          {"p95_pos_err_m", num(s.p95_pos_err_m)},
          {"max_pos_err_m", num(s.max_pos_err_m)},
          {"yaw_rmse_deg", num(s.yaw_rmse_deg)},
          {"p95_yaw_err_deg", num(s.p95_yaw_err_deg)},
          {"max_yaw_err_deg", num(s.max_yaw_err_deg)},
          {"z_rmse_m", num(s.z_rmse_m)},
          {"max_z_err_m", num(s.max_z_err_m)},
          {"roll_pitch_rmse_deg", num(s.roll_pitch_rmse_deg)},
          {"max_roll_pitch_err_deg", num(s.max_roll_pitch_err_deg)}};
}

namespace {

const char* kAxes[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

std::string covHeader(CsvCovariance cov) {
  std::string h;
  if (cov == CsvCovariance::Diagonal)
    for (const char* a : kAxes) h += fmt::format(",var_{}", a);
  if (cov == CsvCovariance::Full)
    for (int i = 0; i < 6; ++i)
      for (int j = i; j < 6; ++j) h += fmt::format(",cov_{}{}", i, j);
  return h + ",ess,particles,seen_through,refined,map_fit";
}

std::string covColumns(const FrameRecord* f, CsvCovariance cov) {
  if (!f) return {};
  std::string s;
  if (cov == CsvCovariance::Diagonal)
    for (int i = 0; i < 6; ++i) s += fmt::format(",{:.6g}", f->covariance(i, i));
  if (cov == CsvCovariance::Full)
    for (int i = 0; i < 6; ++i)
      for (int j = i; j < 6; ++j) s += fmt::format(",{:.6g}", f->covariance(i, j));
  return s + fmt::format(",{:.1f},{},{:.3f},{},{:.3f}", f->ess, f->particles, f->seen_through, f->refined ? 1 : 0, f->map_fit);
}

}  // namespace

void writeCsv(const std::string& path, const TrajectoryMetrics* metrics, const std::vector<FrameRecord>& frames,
              CsvCovariance cov) {
  AtomicFile file(path);
  std::ofstream f(file.tmp());
  if (!f) throw std::runtime_error(fmt::format("{}: cannot write", path));
  auto pose = [](const Pose& p) {
    return fmt::format("{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}", p.x(), p.y(), p.z(), rad2deg(p.roll()),
                       rad2deg(p.pitch()), rad2deg(p.yaw()));
  };
  f << "stamp_ns,x,y,z,roll_deg,pitch_deg,yaw_deg,status";
  if (!metrics) {
    f << covHeader(cov) << "\n";
    for (const auto& e : frames)
      f << fmt::format("{},{},{}{}\n", e.stamp_ns, pose(e.pose), toString(e.status), covColumns(&e, cov));
  } else {
    f << ",t_s,gt_x,gt_y,gt_z,gt_roll_deg,gt_pitch_deg,gt_yaw_deg,dx,dy,dz,pos_err_m,yaw_err_deg,roll_err_deg,"
         "pitch_err_deg,converged" << covHeader(cov) << "\n";
    size_t k = 0;  // both in stamp order: the frame record of each evaluated frame
    for (const auto& e : metrics->frames) {
      while (k < frames.size() && frames[k].stamp_ns < e.stamp_ns) ++k;
      const FrameRecord* rec = k < frames.size() && frames[k].stamp_ns == e.stamp_ns ? &frames[k] : nullptr;
      f << fmt::format("{},{},{},{:.6f},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f},{}{}\n", e.stamp_ns,
                       pose(e.estimate), toString(e.status), e.t_s, pose(e.truth), e.dx, e.dy, e.dz, e.pos_err,
                       rad2deg(e.yaw_err), rad2deg(e.roll_err), rad2deg(e.pitch_err), e.converged ? 1 : 0,
                       covColumns(rec, cov));
    }
  }
  if (!f) throw std::runtime_error(fmt::format("{}: write failed", path));
}

void writeTum(const std::string& path, const std::vector<FrameRecord>& frames) {
  if (auto dir = std::filesystem::path(path).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  TumWriter tum(path);
  for (const auto& f : frames) tum.write({f.stamp_ns, f.pose});
}

std::optional<TrajectoryMetrics> evaluate(const JobResult& r) {
  if (r.truth.empty()) return std::nullopt;
  MetricsOptions mo;
  // Times count from the filter's start, never after the first estimate: t_s and
  // converged_after_s are not negative whatever clock the recording's stamps are on.
  mo.start_ns = r.init_ns;
  if (!r.frames.empty() && (mo.start_ns == 0 || r.frames.front().stamp_ns < mo.start_ns)) mo.start_ns = r.frames.front().stamp_ns;
  return evaluateTrajectory(estimatesOf(r.frames), GroundTruth(r.truth), mo);
}

nlohmann::json resultJson(const JobResult& r, const TrajectoryMetrics* metrics) {
  const double ups = r.filter_s > 0 ? double(r.updates) / r.filter_s : 0.0;
  nlohmann::json j = {{"input", r.input}, {"format", r.format}, {"init", r.init_mode}, {"frames", r.frames.size()},
                      {"updates", r.updates}, {"updates_per_s", ups}, {"wall_s", r.wall_s}, {"filter_s", r.filter_s},
                      {"particles", r.final_particles}, {"status", toString(r.final_status)},
                      {"counters", r.counters}};
  // Map fit (mcl.fit): the share of beams the map explains at the estimate, smoothed.
  std::vector<double> fit;
  for (const auto& f : r.frames)
    if (f.map_fit >= 0) fit.push_back(f.map_fit);
  if (!fit.empty())
    j["map_fit"] = {{"last", fit.back()}, {"min", *std::min_element(fit.begin(), fit.end())}, {"p05", percentile(fit, 5)},
                    {"p50", percentile(fit, 50)}};
  else
    j["map_fit"] = nullptr;
  if (!metrics) return j;
  j["evaluated_frames"] = metrics->all.frames;
  j["skipped_frames"] = metrics->skipped;
  const nlohmann::json all = summaryJson(metrics->all);  // a named object: items() refers to it
  for (const auto& [k, v] : all.items())
    if (k != "frames") j[k] = v;
  j["converged_after_s"] = metrics->converged_after_s ? num(*metrics->converged_after_s) : nlohmann::json(nullptr);
  j["after_convergence"] = summaryJson(metrics->after_convergence);
  nlohmann::json by_status = nlohmann::json::object();
  for (size_t s = 0; s < metrics->frames_by_status.size(); ++s)
    by_status[toString(static_cast<MclStatus>(s))] = metrics->frames_by_status[s];
  j["frames_by_status"] = by_status;
  return j;
}

void drawPlot(const Mesh& mesh, const JobResult& r, const TrajectoryMetrics* metrics, const std::string& png_path,
              const std::string& command) {
  viz::LocalizePlotData plot = r.plot;
  for (const auto& p : r.truth)
    if (domain::validPose(p.pose)) plot.truth_path.emplace_back(float(p.pose.x()), float(p.pose.y()));
  const double ups = r.filter_s > 0 ? double(r.updates) / r.filter_s : 0.0;
  plot.title = fmt::format("{} {} ({}, {} updates, {:.1f} updates/s)", command,
                           std::filesystem::path(r.input).filename().string(), r.init_mode, r.updates, ups);
  if (metrics) {
    const auto& s = metrics->all;
    plot.legend = fmt::format("ATE {:.3f} m, p95 {:.3f} m, yaw RMSE {:.2f} deg, p95 {:.2f} deg", s.ate_rmse_m,
                              s.p95_pos_err_m, s.yaw_rmse_deg, s.p95_yaw_err_deg);
    if (metrics->converged_after_s)
      plot.legend += fmt::format("\nconverged after {:.1f} s; then p95 {:.3f} m, {:.2f} deg", *metrics->converged_after_s,
                                 metrics->after_convergence.p95_pos_err_m, metrics->after_convergence.p95_yaw_err_deg);
    else plot.legend += "\nnot converged (0.2 m, 5 deg for 1 s)";
  }
  if (auto dir = std::filesystem::path(png_path).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  viz::drawLocalization(mesh, plot, png_path);
}

}  // namespace polyloc::reloc
