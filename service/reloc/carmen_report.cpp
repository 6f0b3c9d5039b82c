#include "reloc/carmen_report.hpp"
#include "reloc/report.hpp"
#include "viz/error_strips.hpp"
#include "viz/topview.hpp"

#include <polyloc/eval/stats.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <map>

namespace polyloc::reloc {
namespace {

// A test scan leaves the position open along the heading (a corridor) when its alignment's std
// along it exceeds this (m).
constexpr double kOpenAlongM = 0.05;

// The errors of a run split by what the scans pin down: frames whose scan fixes the position in
// every direction, and frames that leave it open along the heading (corridors).
nlohmann::json splitByObservability(const TrajectoryMetrics& m, const std::vector<StampedPose>& truth,
                                    const std::vector<size_t>& positions, const CarmenMap& map) {
  std::map<int64_t, size_t> index;
  for (size_t k = 0; k < truth.size() && k < positions.size(); ++k) index[truth[k].stamp_ns] = positions[k];
  std::vector<FrameError> pinned, open;
  for (const FrameError& f : m.frames) {
    auto it = index.find(f.stamp_ns);
    if (it == index.end() || it->second >= map.floor_std_along.size()) continue;
    (map.floor_std_along[it->second] > kOpenAlongM ? open : pinned).push_back(f);
  }
  auto part = [](const std::vector<FrameError>& v) {
    const ErrorSummary s = summarize(v);
    return nlohmann::json{{"frames", s.frames}, {"ate_rmse_m", num(s.ate_rmse_m)}, {"p95_pos_err_m", num(s.p95_pos_err_m)}};
  };
  return {{"pinned", part(pinned)}, {"open_along_heading", part(open)}, {"open_threshold_m", kOpenAlongM}};
}

nlohmann::json headingJson(const TrajectoryMetrics& m) {
  const HeadingSplit h = splitByHeading(m.frames);
  return {{"along_rmse_m", num(h.along_rmse_m)}, {"across_rmse_m", num(h.across_rmse_m)}};
}

size_t framesBeyond(const TrajectoryMetrics& m, double d) {
  size_t n = 0;
  for (const auto& f : m.frames) n += f.converged && f.pos_err > d;
  return n;
}

// The case's truth, as its run had it (the stamps of its test scans).
std::vector<StampedPose> caseTruth(const CarmenCase& c) { return c.job.truth; }

double ratio(double a, double b) { return b > 0 ? a / b : std::numeric_limits<double>::quiet_NaN(); }

struct GlobalSummary {
  size_t ok = 0;
  size_t tracking_beyond_0_5m = 0;  // over every trial's updates
  std::vector<double> first;
  double filter_s = 0;
};
GlobalSummary summarizeGlobal(const std::vector<CarmenGlobalTrial>& trials) {
  GlobalSummary g;
  for (const auto& t : trials) {
    g.ok += t.success, g.filter_s += t.filter_s, g.tracking_beyond_0_5m += t.tracking_beyond_0_5m;
    if (t.success) g.first.push_back(t.first_within);
  }
  return g;
}

std::string cm(double m) { return std::isfinite(m) ? fmt::format("{:.1f}", 100 * m) : "n/a"; }

}  // namespace

nlohmann::json carmenCaseJson(const CarmenCase& c, const CarmenEvalResult& r) {
  nlohmann::json j = c.unusable.empty() ? resultJson(c.job, c.metrics ? &*c.metrics : nullptr) : nlohmann::json::object();
  j.erase("input");
  j["name"] = c.name();
  j["map"] = c.map_style;
  j["odometry"] = c.odometry;
  if (c.odometry != "own") j["drift"] = describeDrift(c.drift);
  j["decimate"] = c.decimate;
  j["stamps"] = c.stamps;
  j["odometry_messages"] = c.odometry_messages;
  j["odometry_dropped"] = c.odometry_dropped;
  j["odometry_only"] = summaryJson(c.odometry_only.all);
  if (!c.unusable.empty()) j["unusable"] = c.unusable;
  if (c.floor) j["floor"] = summaryJson(c.floor->all);
  if (!c.metrics) return j;
  const CarmenMap& map = r.maps[c.map];
  j["frames_beyond_0_5m_after_convergence"] = framesBeyond(*c.metrics, kCarmenLostM);
  const Consistency& k = c.consistency;
  j["frames_tracking_beyond_0_5m"] = k.tracking_beyond;
  j["worst_tracking_err_m"] = k.worst_tracking_err_m;
  j["jumps"] = k.jumps;
  j["unannounced_jumps"] = k.unannounced_jumps;
  j["worst_unannounced_jump_m"] = k.worst_unannounced_jump_m;
  j["nees"] = {{"tracking_frames", k.tracking}, {"mean", num(k.nees_mean)}, {"over_95", num(k.nees_over_95)}};
  if (c.floor) {
    j["by_observability"] = splitByObservability(*c.metrics, caseTruth(c), c.test_positions, map);
    j["ate_over_floor"] = num(ratio(c.metrics->all.ate_rmse_m, c.floor->all.ate_rmse_m));
    j["p95_over_floor"] = num(ratio(c.metrics->all.p95_pos_err_m, c.floor->all.p95_pos_err_m));
  }
  j["by_heading"] = headingJson(*c.metrics);
  j["range_bias_m"] = c.job.final_range_bias;
  j["odometry_scale"] = {{"translation", c.job.final_odometry_scale_translation}, {"rotation", c.job.final_odometry_scale_rotation}};
  return j;
}

nlohmann::json carmenMapJson(const CarmenMap& m, const CarmenEvalResult& r, const CarmenEvalOptions& o) {
  nlohmann::json j = {{"style", m.map.style}, {"description", describeLogMapStyle(m.map.style)},
                      {"cells_x", m.map.grid.width}, {"cells_y", m.map.grid.height},
                      {"resolution_m", m.map.grid.resolution}, {"triangles", m.map.mesh.numTriangles()}, {"build_s", m.map_s}};
  if (m.floor) {
    nlohmann::json f = summaryJson(m.floor->all);
    f["refined"] = m.floor_refined;
    f["refused"] = m.floor_refused;
    std::vector<size_t> all(r.truth.size());
    for (size_t k = 0; k < all.size(); ++k) all[k] = k;
    f["by_observability"] = splitByObservability(*m.floor, r.truth, all, m);
    f["by_heading"] = headingJson(*m.floor);
    f["seconds"] = m.floor_s;
    f["range_bias_m"] = m.range_bias;
    j["floor"] = f;
    auto pct = [](const std::vector<double>& v) {
      return nlohmann::json{{"p01", percentile(v, 1)}, {"p05", percentile(v, 5)}, {"p50", percentile(v, 50)},
                            {"p95", percentile(v, 95)}, {"max", percentile(v, 100)}};
    };
    j["fit_check"] = {{"aligned", pct(m.seen_through_aligned)}, {"displaced_0_5m", pct(m.seen_through_0_5m)},
                      {"displaced_2m", pct(m.seen_through_2m)}, {"explained_aligned", pct(m.explained_aligned)}};
  }
  const GlobalSummary g = summarizeGlobal(m.global);
  nlohmann::json trials = nlohmann::json::array();
  for (const auto& t : m.global)
    trials.push_back({{"start", t.test_index}, {"success", t.success}, {"updates", t.updates}, {"first_within", t.first_within},
                      {"pos_err_m", t.pos_err}, {"yaw_err_deg", t.yaw_err_deg}, {"tracking_beyond_0_5m", t.tracking_beyond_0_5m}});
  j["global"] = {{"trials", m.global.size()}, {"succeeded", g.ok},
                 {"fraction", m.global.empty() ? 0.0 : double(g.ok) / double(m.global.size())},
                 {"updates", o.global_updates}, {"pos_tol_m", o.global_pos_tol}, {"yaw_tol_deg", o.global_yaw_tol_deg},
                 {"median_first_within", g.first.empty() ? nlohmann::json(nullptr) : nlohmann::json(percentile(g.first, 50))},
                 {"tracking_beyond_0_5m", g.tracking_beyond_0_5m}, {"filter_s", g.filter_s}, {"results", trials}};
  return j;
}

nlohmann::json carmenJson(const CarmenEvalResult& r, const CarmenEvalOptions& o) {
  nlohmann::json j = {{"log", r.log}, {"topic", r.topic}, {"geometry", r.geometry}, {"scans", r.scans},
                      {"map_scans", r.map_scans}, {"test_scans", r.test_scans}, {"log_odometry", r.log_odometry},
                      {"config", r.config.file}, {"seed", o.seed}, {"wall_s", r.wall_s}};
  nlohmann::json maps = nlohmann::json::array(), cases = nlohmann::json::array();
  for (const auto& m : r.maps) maps.push_back(carmenMapJson(m, r, o));
  for (const auto& c : r.cases) cases.push_back(carmenCaseJson(c, r));
  j["maps"] = maps;
  j["cases"] = cases;
  return j;
}

std::string carmenText(const CarmenEvalResult& r, const CarmenEvalOptions& o) {
  std::string s = fmt::format("log        {}: {} scans on {} ({}), {} ODOM messages; {} map scans, {} test scans\n", r.log, r.scans,
                              r.topic, r.geometry, r.log_odometry, r.map_scans, r.test_scans);
  for (const auto& m : r.maps) {
    s += fmt::format("map        {:<9} {} x {} cells at {} m -> {} triangles ({:.1f} s)", m.map.style, m.map.grid.width,
                     m.map.grid.height, m.map.grid.resolution, m.map.mesh.numTriangles(), m.map_s);
    if (m.floor)
      s += fmt::format("; floor RMSE {} cm, p95 {} cm, yaw RMSE {:.2f} deg", cm(m.floor->all.ate_rmse_m),
                       cm(m.floor->all.p95_pos_err_m), m.floor->all.yaw_rmse_deg);
    if (!m.global.empty()) {
      const GlobalSummary g = summarizeGlobal(m.global);
      s += fmt::format("; global {}/{} within {} m, {} deg after {} updates, {} updates tracking beyond 0.5 m", g.ok,
                       m.global.size(), o.global_pos_tol, o.global_yaw_tol_deg, o.global_updates, g.tracking_beyond_0_5m);
    }
    s += "\n";
  }
  s += fmt::format("{:<24} {:>6} {:>8} {:>8} {:>7} {:>8} {:>8} {:>9} {:>11} {:>6} {:>6} {:>9}\n", "case (map/odometry/xN)", "frames",
                   "ATE cm", "floor cm", "x floor", "p95 cm", "worst cm", "track>.5m", "jumps(unann)", "NEES", "reloc",
                   "odo-only");
  for (const auto& c : r.cases) {
    if (!c.unusable.empty()) {
      s += fmt::format("{:<24} not localised: {}\n", c.name(), c.unusable);
      continue;
    }
    if (!c.metrics) {
      s += fmt::format("{:<24} no estimate could be evaluated\n", c.name());
      continue;
    }
    const ErrorSummary& e = c.metrics->all;
    const double floor = c.floor ? c.floor->all.ate_rmse_m : std::numeric_limits<double>::quiet_NaN();
    s += fmt::format("{:<24} {:>6} {:>8} {:>8} {:>7.2f} {:>8} {:>8} {:>9} {:>6}({:>4}) {:>6.1f} {:>6} {:>9}\n", c.name(), e.frames,
                     cm(e.ate_rmse_m), cm(floor), ratio(e.ate_rmse_m, floor), cm(e.p95_pos_err_m), cm(e.max_pos_err_m),
                     c.consistency.tracking_beyond, c.consistency.jumps, c.consistency.unannounced_jumps, c.consistency.nees_mean,
                     c.job.counters.count("relocalizations") ? c.job.counters.at("relocalizations") : 0,
                     cm(c.odometry_only.all.ate_rmse_m));
  }
  return s;
}

void drawCarmenStrips(const CarmenEvalResult& r, const std::string& png_path) {
  viz::ErrorStripGrid g;
  g.title = fmt::format("polyloc eval carmen {}: {} test scans", std::filesystem::path(r.log).filename().string(), r.test_scans);
  g.limit_m = kCarmenLostM;
  // Rows: map style x decimation; columns: odometry (in case order). Roughly square for the matrix.
  std::vector<std::string> columns;
  std::vector<size_t> decimations;
  for (const auto& c : r.cases) {
    if (std::find(columns.begin(), columns.end(), c.odometry) == columns.end()) columns.push_back(c.odometry);
    if (std::find(decimations.begin(), decimations.end(), c.decimate) == decimations.end()) decimations.push_back(c.decimate);
  }
  for (const auto& odo : columns) g.column_labels.push_back(odo + " odometry");
  for (const auto& m : r.maps)
    for (size_t dec : decimations) g.row_labels.push_back(fmt::format("{} x{}", m.map.style, dec));
  g.strips.resize(g.row_labels.size() * columns.size());
  for (auto& s : g.strips) s.empty = true;
  for (const auto& c : r.cases) {
    const size_t col = size_t(std::find(columns.begin(), columns.end(), c.odometry) - columns.begin());
    const size_t row = c.map * decimations.size() + size_t(std::find(decimations.begin(), decimations.end(), c.decimate) - decimations.begin());
    viz::ErrorStrip& s = g.strips[row * columns.size() + col];
    if (!c.metrics) continue;
    s.empty = false;
    const ErrorSummary& e = c.metrics->all;
    const double floor = c.floor ? c.floor->all.ate_rmse_m : std::numeric_limits<double>::quiet_NaN();
    s.title = fmt::format("ATE {} cm = {:.2f}x floor, tracking>0.5m {}, jumps {}", cm(e.ate_rmse_m), ratio(e.ate_rmse_m, floor),
                          c.consistency.tracking_beyond, c.consistency.unannounced_jumps);
    for (const FrameError& f : c.metrics->frames) s.t_s.push_back(f.t_s), s.error_m.push_back(f.pos_err), s.status.push_back(f.status);
    if (c.floor)
      for (const FrameError& f : c.floor->frames) s.floor_t_s.push_back(f.t_s), s.floor_m.push_back(f.pos_err);
  }
  viz::drawErrorStrips(g, png_path);
}

void drawCarmenPlot(const CarmenEvalResult& r, const CarmenEvalOptions& o, const std::string& png_path) {
  if (r.maps.empty()) return;
  const Mesh& mesh = r.maps.front().map.mesh;
  const Eigen::AlignedBox3f b3 = mesh.bounds();
  const Eigen::AlignedBox2f b(b3.min().head<2>(), b3.max().head<2>());
  const float extent = std::max(b.sizes().x(), b.sizes().y());
  viz::TopView view(b, std::clamp(3000.f / std::max(extent, 1.f), 2.f, 40.f));
  view.drawMeshSlice(mesh, 0.3f, &viz::kGray, 1);
  auto path = [&](const std::vector<Eigen::Vector2f>& p, viz::Color c, int w) {
    for (size_t i = 1; i < p.size(); ++i) view.drawLine(p[i - 1], p[i], c, w);
  };
  auto xy = [](const Pose& p) { return Eigen::Vector2f(float(p.x()), float(p.y())); };
  std::vector<Eigen::Vector2f> truth;
  for (const auto& t : r.truth) truth.push_back(xy(t.pose));
  std::string legend = fmt::format("polyloc eval carmen {} ({} map): {} test scans; black truth",
                                   std::filesystem::path(r.log).filename().string(), r.maps.front().map.style, r.test_scans);
  // The first drift case at its first decimation, and the own case, on the first map.
  std::vector<const CarmenCase*> shown;
  for (const auto& c : r.cases)
    if (c.map == 0 && (shown.empty() || c.odometry == "own") && c.metrics) shown.push_back(&c);
  const viz::Color colors[2] = {viz::kBlue, viz::kOrange};
  for (size_t k = 0; k < shown.size() && k < 2; ++k) {
    const CarmenCase& c = *shown[k];
    std::vector<Eigen::Vector2f> odo, est;
    for (const auto& f : c.odometry_only.frames) odo.push_back(xy(f.estimate));
    for (const auto& f : c.job.frames) est.push_back(xy(f.pose));
    if (k == 0) path(odo, viz::kGray, 1);
    path(est, colors[k], 2);
    const HeadingSplit h = splitByHeading(c.metrics->frames);
    legend += fmt::format(", {} {} (ATE {:.3f} m: {:.3f} along the heading, {:.3f} across)", k == 0 ? "blue" : "orange", c.name(),
                          c.metrics->all.ate_rmse_m, h.along_rmse_m, h.across_rmse_m);
  }
  path(truth, viz::kBlack, 1);
  if (!shown.empty()) legend += fmt::format(", grey {} odometry alone", shown.front()->name());
  const CarmenMap& m = r.maps.front();
  size_t ok = 0;
  for (const auto& t : m.global) {
    ok += t.success;
    view.drawPose(t.truth, t.success ? viz::kGreen : viz::kRed, 0.4f);
  }
  if (!m.global.empty())
    legend += fmt::format("\nglobal: {}/{} (green) within {} m, {} deg after {} updates", ok, m.global.size(), o.global_pos_tol,
                          o.global_yaw_tol_deg, o.global_updates);
  if (m.floor) {
    const HeadingSplit h = splitByHeading(m.floor->frames);
    legend += fmt::format("\nfloor (test scans aligned to the map): RMSE {:.3f} m: {:.3f} along the heading, {:.3f} across",
                          m.floor->all.ate_rmse_m, h.along_rmse_m, h.across_rmse_m);
  }
  view.drawLegend(legend);
  view.drawScaleBar();
  view.save(png_path);
}

}  // namespace polyloc::reloc
