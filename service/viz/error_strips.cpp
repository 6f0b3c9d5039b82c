#include "viz/error_strips.hpp"
#include "viz/png_file.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace polyloc::viz {
namespace {

constexpr int kPanelW = 340, kPanelH = 130, kLabelW = 110, kHeaderH = 60, kTitleH = 16;
constexpr double kMinErr = 0.001, kMaxErr = 5.0;

cv::Scalar statusColor(MclStatus s) {
  switch (s) {
    case MclStatus::Tracking: return {60, 160, 30};    // green (BGR)
    case MclStatus::Uncertain: return {20, 140, 240};  // orange
    case MclStatus::Lost: return {30, 30, 220};        // red
    default: return {150, 150, 150};
  }
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.38, cv::Scalar c = {0, 0, 0}) {
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, c, 1, cv::LINE_AA);
}

// One panel at (x0, y0): axes, grid lines at 1 cm, 10 cm, 1 m, the limit, the floor, the frames.
void drawPanel(cv::Mat& img, int x0, int y0, const ErrorStrip& s, double limit_m) {
  const int px0 = x0 + 4, py0 = y0 + kTitleH, pw = kPanelW - 8, ph = kPanelH - kTitleH - 6;
  cv::rectangle(img, {px0, py0}, {px0 + pw, py0 + ph}, {200, 200, 200}, 1);
  text(img, s.title, {x0 + 4, y0 + 12}, 0.36);
  if (s.empty) {
    text(img, "not run", {px0 + pw / 2 - 25, py0 + ph / 2}, 0.45, {120, 120, 120});
    return;
  }
  const double l0 = std::log10(kMinErr), l1 = std::log10(kMaxErr);
  auto yOf = [&](double e) {
    const double l = std::log10(std::clamp(e, kMinErr, kMaxErr));
    return py0 + ph - int(std::lround((l - l0) / (l1 - l0) * ph));
  };
  double t_max = 1e-9;
  for (double t : s.t_s) t_max = std::max(t_max, t);
  for (double t : s.floor_t_s) t_max = std::max(t_max, t);
  auto xOf = [&](double t) { return px0 + int(std::lround(std::clamp(t / t_max, 0.0, 1.0) * pw)); };
  const std::pair<double, const char*> marks[] = {{0.01, "1cm"}, {0.1, "10cm"}, {1.0, "1m"}};
  for (const auto& [e, label] : marks) {
    cv::line(img, {px0, yOf(e)}, {px0 + pw, yOf(e)}, {225, 225, 225}, 1);
    text(img, label, {px0 + 2, yOf(e) - 2}, 0.3, {150, 150, 150});
  }
  for (int x = px0; x < px0 + pw; x += 8) cv::line(img, {x, yOf(limit_m)}, {std::min(x + 4, px0 + pw), yOf(limit_m)}, {40, 40, 220}, 1);
  for (size_t k = 1; k < s.floor_m.size() && k < s.floor_t_s.size(); ++k)
    cv::line(img, {xOf(s.floor_t_s[k - 1]), yOf(s.floor_m[k - 1])}, {xOf(s.floor_t_s[k]), yOf(s.floor_m[k])}, {170, 170, 170}, 1,
             cv::LINE_AA);
  for (size_t k = 0; k < s.error_m.size() && k < s.t_s.size(); ++k) {
    const MclStatus st = k < s.status.size() ? s.status[k] : MclStatus::Tracking;
    cv::circle(img, {xOf(s.t_s[k]), yOf(s.error_m[k])}, 1, statusColor(st), cv::FILLED);
  }
}

}  // namespace

void drawErrorStrips(const ErrorStripGrid& g, const std::string& png_path) {
  const size_t rows = g.row_labels.size(), cols = g.column_labels.size();
  if (rows == 0 || cols == 0 || g.strips.size() != rows * cols)
    throw std::invalid_argument("error strips: " + std::to_string(g.strips.size()) + " strips for " + std::to_string(rows) +
                                " x " + std::to_string(cols) + " panels");
  cv::Mat img(kHeaderH + int(rows) * kPanelH + 10, kLabelW + int(cols) * kPanelW + 10, CV_8UC3, cv::Scalar(255, 255, 255));
  text(img, g.title, {8, 18}, 0.5);
  text(img, "planar error per frame, log scale 1 mm .. 5 m; green tracking, orange uncertain, red lost; grey line: the map's "
            "floor; dashed red: " + std::to_string(int(std::lround(g.limit_m * 100))) + " cm",
       {8, 36}, 0.4, {80, 80, 80});
  for (size_t c = 0; c < cols; ++c) text(img, g.column_labels[c], {kLabelW + int(c) * kPanelW + 6, kHeaderH - 6}, 0.42);
  for (size_t r = 0; r < rows; ++r) {
    text(img, g.row_labels[r], {6, kHeaderH + int(r) * kPanelH + kPanelH / 2}, 0.45);
    for (size_t c = 0; c < cols; ++c)
      drawPanel(img, kLabelW + int(c) * kPanelW, kHeaderH + int(r) * kPanelH, g.strips[r * cols + c], g.limit_m);
  }
  writePng(img, png_path);
}

}  // namespace polyloc::viz
