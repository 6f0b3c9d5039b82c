#include "viz/fusion_plot.hpp"
#include "viz/png_file.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc::viz {
namespace {

constexpr int kPanel = 640, kMargin = 30, kTitle = 60;

// One projection: axes (a, b) of the world as the panel's right and up.
cv::Mat panel(const Mesh& mesh, const std::vector<Pose>& path, int a, int b, const std::string& label) {
  Eigen::AlignedBox3f box = mesh.bounds();
  for (const Pose& p : path) box.extend(p.translation().cast<float>());
  const float ext = std::max({box.sizes()[a], box.sizes()[b], 1e-3f});
  const float scale = float(kPanel - 2 * kMargin) / ext;
  auto px = [&](const Eigen::Vector3f& v) {
    return cv::Point(kMargin + int((v[a] - box.min()[a]) * scale), kPanel - kMargin - int((v[b] - box.min()[b]) * scale));
  };
  // Surface density: triangle area per pixel, on a log scale (walls seen edge-on are dark).
  cv::Mat density(kPanel, kPanel, CV_32F, cv::Scalar(0));
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3f &p0 = mesh.vertices[t[0]], &p1 = mesh.vertices[t[1]], &p2 = mesh.vertices[t[2]];
    const cv::Point c = px((p0 + p1 + p2) / 3.f);
    if (c.x >= 0 && c.y >= 0 && c.x < kPanel && c.y < kPanel) density.at<float>(c) += 0.5f * (p1 - p0).cross(p2 - p0).norm();
  }
  double hi = 0;
  cv::minMaxLoc(density, nullptr, &hi);
  cv::Mat img(kPanel, kPanel, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int y = 0; y < kPanel; ++y)
    for (int x = 0; x < kPanel; ++x)
      if (const float d = density.at<float>(y, x); d > 0) {
        const int g = 200 - int(180 * std::log1p(d) / std::log1p(float(hi)));
        img.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(g), uchar(g), uchar(g));
      }
  for (size_t i = 1; i < path.size(); ++i)
    cv::line(img, px(path[i - 1].translation().cast<float>()), px(path[i].translation().cast<float>()),
             cv::Scalar(220, 90, 40), 2, cv::LINE_AA);  // BGR: blue
  if (!path.empty()) cv::circle(img, px(path.front().translation().cast<float>()), 5, cv::Scalar(60, 160, 30), -1);
  cv::putText(img, label, {kMargin, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const int bar = int(std::round(scale));  // 1 m
  cv::line(img, {kMargin, kPanel - 10}, {kMargin + bar, kPanel - 10}, cv::Scalar(0, 0, 0), 2);
  cv::putText(img, "1 m", {kMargin + bar + 5, kPanel - 6}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return img;
}

}  // namespace

void drawFusion(const Mesh& mesh, const std::vector<Pose>& path, const std::string& title, const std::string& png) {
  cv::Mat views;
  cv::hconcat(panel(mesh, path, 0, 1, "along z: x right, y up"), panel(mesh, path, 0, 2, "along y: x right, z up"), views);
  cv::Mat out(views.rows + kTitle, views.cols, CV_8UC3, cv::Scalar(255, 255, 255));
  views.copyTo(out(cv::Rect(0, kTitle, views.cols, views.rows)));
  int y = 22;
  for (size_t start = 0; start < title.size(); y += 22) {  // lines of the title
    const size_t end = std::min(title.find('\n', start), title.size());
    cv::putText(out, title.substr(start, end - start), {10, y}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    start = end + 1;
  }
  writePng(out, png);
}

}  // namespace polyloc::viz
