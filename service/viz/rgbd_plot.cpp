#include "viz/rgbd_plot.hpp"
#include "viz/png_file.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace polyloc::viz {
namespace {

const cv::Scalar kInk(0, 0, 0);

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.5) {
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, kInk, 1, cv::LINE_AA);
}

// Depth as grey, near bright; no depth black.
cv::Mat depthImage(const std::vector<float>& d, int w, int h, float far) {
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int i = 0; i < w * h; ++i)
    if (std::isfinite(d[i]) && d[i] > 0) {
      const uchar g = uchar(255 - std::clamp(d[i] / far, 0.f, 1.f) * 215);
      img.at<cv::Vec3b>(i / w, i % w) = cv::Vec3b(g, g, g);
    }
  return img;
}

// Labels (BGR): good grey, outlier red, ambiguous yellow, unlabelled blue; removed by the filter:
// an outlier green (caught), a good pixel magenta (lost).
cv::Mat labelImage(const RgbdEvalResult::Sample& s, int w, int h) {
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int i = 0; i < w * h; ++i) {
    const auto l = RgbdLabel(s.label[i]);
    const bool removed = !s.kept[i];
    cv::Vec3b c(0, 0, 0);
    if (l == RgbdLabel::kGood) c = removed ? cv::Vec3b(200, 0, 200) : cv::Vec3b(150, 150, 150);
    else if (l == RgbdLabel::kOutlier) c = removed ? cv::Vec3b(0, 170, 0) : cv::Vec3b(0, 0, 230);
    else if (l == RgbdLabel::kAmbiguous) c = cv::Vec3b(0, 200, 230);
    else if (l == RgbdLabel::kUnlabelled) c = cv::Vec3b(200, 120, 40);
    img.at<cv::Vec3b>(i / w, i % w) = c;
  }
  return img;
}

// The floor over the frames: translation (cm, blue) and rotation (deg, red) against frame index.
cv::Mat floorPlot(const RgbdEvalResult& r, int width) {
  const int h = 260, l = 60, rm = 20, t = 30, b = 40;
  cv::Mat img(h, width, CV_8UC3, cv::Scalar(255, 255, 255));
  double ymax = 1e-3;
  int64_t first = 0, last = 1;
  for (const RgbdFrameResult& f : r.frames)
    if (f.floor_ok) ymax = std::max({ymax, 100 * f.floor_translation, f.floor_rotation * 180 / M_PI});
  if (!r.frames.empty()) first = r.frames.front().index, last = std::max(r.frames.back().index, first + 1);
  ymax *= 1.1;
  auto px = [&](int64_t i, double y) {
    return cv::Point(l + int(double(i - first) / double(last - first) * (width - l - rm)), h - b - int(y / ymax * (h - t - b)));
  };
  cv::rectangle(img, {l, t}, {width - rm, h - b}, kInk, 1);
  for (const RgbdFrameResult& f : r.frames)
    if (f.floor_ok) {
      cv::circle(img, px(f.index, 100 * f.floor_translation), 2, cv::Scalar(200, 80, 30), -1);
      cv::circle(img, px(f.index, f.floor_rotation * 180 / M_PI), 2, cv::Scalar(30, 30, 220), -1);
    }
  text(img, "agreement floor per frame: ICP from the ground truth vs the ground truth; blue: translation (cm), red: rotation (deg)", {l, 20});
  char top[32];
  std::snprintf(top, sizeof top, "%.2f", ymax);
  text(img, top, {5, t + 10}, 0.4);
  text(img, "0", {40, h - b}, 0.4);
  text(img, "frame " + std::to_string(first), {l, h - b + 18}, 0.4);
  text(img, "frame " + std::to_string(last), {width - rm - 90, h - b + 18}, 0.4);
  return img;
}

}  // namespace

void drawRgbdEval(const RgbdEvalResult& r, const std::string& title, const std::string& png) {
  const int w = r.camera.width, h = r.camera.height;
  std::vector<cv::Mat> rows;
  cv::Mat head(70, 3 * w, CV_8UC3, cv::Scalar(255, 255, 255));
  int y = 22;
  for (size_t start = 0; start < title.size(); y += 22) {
    const size_t end = std::min(title.find('\n', start), title.size());
    text(head, title.substr(start, end - start), {10, y});
    start = end + 1;
  }
  rows.push_back(head);
  if (r.sample.index >= 0 && w > 0) {
    cv::Mat frame;
    cv::hconcat(std::vector<cv::Mat>{depthImage(r.sample.measured, w, h, 4.f), depthImage(r.sample.rendered, w, h, 4.f),
                                     labelImage(r.sample, w, h)},
                frame);
    cv::Mat caption(26, 3 * w, CV_8UC3, cv::Scalar(255, 255, 255));
    text(caption, "frame " + std::to_string(r.sample.index) + ": measured depth", {10, 18});
    text(caption, "the mesh rendered at the ground truth", {w + 10, 18});
    text(caption, "good grey, outlier red, ambiguous yellow, no mesh blue; filter removed: outlier green, good magenta",
         {2 * w + 4, 18}, 0.37);
    rows.push_back(caption);
    rows.push_back(frame);
  }
  rows.push_back(floorPlot(r, 3 * std::max(w, 200)));
  for (cv::Mat& m : rows)
    if (m.cols != rows.front().cols) cv::resize(m, m, {rows.front().cols, m.rows});
  cv::Mat out;
  cv::vconcat(rows, out);
  writePng(out, png);
}

}  // namespace polyloc::viz
