#include "viz/topview.hpp"
#include "viz/png_file.hpp"

#include <polyloc/map/slice.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

namespace polyloc::viz {

namespace {
cv::Scalar bgr(Color c) { return cv::Scalar(c[2], c[1], c[0]); }
}  // namespace

Color labelColor(const std::string& label) {
  if (label == "glass") return kCyan;
  if (label == "door") return {150, 90, 40};
  if (label == "danger") return kRed;
  if (label == "ramp") return kOrange;
  if (label == "floor") return kGray;
  if (label == "wall" || label.empty()) return kBlack;
  return {70, 90, 140};  // furniture and other objects
}

struct TopView::Canvas {
  cv::Mat img;
  Eigen::AlignedBox2f bounds;
  float scale;
  int margin;
  cv::Point px(const Eigen::Vector2f& p) const {
    return {static_cast<int>(std::lround(margin + (p.x() - bounds.min().x()) * scale)),
            static_cast<int>(std::lround(img.rows - margin - (p.y() - bounds.min().y()) * scale))};
  }
};

TopView::TopView(const Eigen::AlignedBox2f& bounds, float px_per_m, int margin_px)
    : canvas_(new Canvas) {
  canvas_->bounds = bounds;
  canvas_->scale = px_per_m;
  canvas_->margin = margin_px;
  const Eigen::Vector2f size = bounds.sizes();
  const int w = static_cast<int>(std::ceil(size.x() * px_per_m)) + 2 * margin_px;
  const int h = static_cast<int>(std::ceil(size.y() * px_per_m)) + 2 * margin_px;
  if (w <= 0 || h <= 0 || w > 20000 || h > 20000)
    throw std::invalid_argument("TopView: picture size " + std::to_string(w) + "x" +
                                std::to_string(h) + " px is out of range; check the bounds and scale");
  canvas_->img = cv::Mat(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
}

TopView::~TopView() = default;
int TopView::width() const { return canvas_->img.cols; }
int TopView::height() const { return canvas_->img.rows; }

void TopView::drawMeshSlice(const Mesh& mesh, float height, const Color* color, int thickness) {
  for (const SliceSegment& s : sliceMesh(mesh, height)) {
    const Color c = color ? *color : labelColor(mesh.label_names[s.label]);
    cv::line(canvas_->img, canvas_->px(s.a), canvas_->px(s.b), bgr(c), thickness, cv::LINE_AA);
  }
}

void TopView::drawGrid(const OccupancyGrid& g) {
  const float r = float(g.resolution);
  for (size_t y = 0; y < g.height; ++y)
    for (size_t x = 0; x < g.width; ++x) {
      const int8_t v = g.at(x, y);
      if (v == OccupancyGrid::kFree) continue;
      const Eigen::Vector2f lo(float(g.origin_x) + r * float(x), float(g.origin_y) + r * float(y));
      const cv::Scalar c = v == OccupancyGrid::kOccupied ? cv::Scalar(0, 0, 0) : cv::Scalar(215, 215, 215);
      cv::rectangle(canvas_->img, canvas_->px(lo), canvas_->px(lo + Eigen::Vector2f(r, r)), c, cv::FILLED);
    }
}

void TopView::drawLine(const Eigen::Vector2f& a, const Eigen::Vector2f& b, Color c, int thickness) {
  cv::line(canvas_->img, canvas_->px(a), canvas_->px(b), bgr(c), thickness, cv::LINE_AA);
}

void TopView::drawPoint(const Eigen::Vector2f& p, Color c, int radius_px) {
  cv::circle(canvas_->img, canvas_->px(p), radius_px, bgr(c), cv::FILLED, cv::LINE_AA);
}

void TopView::drawPose(const Pose& pose, Color c, float radius_m) {
  const Eigen::Vector2f o(pose.x(), pose.y());
  const int r = std::max(2, static_cast<int>(radius_m * canvas_->scale));
  cv::circle(canvas_->img, canvas_->px(o), r, bgr(c), 2, cv::LINE_AA);
  const Eigen::Vector2f tip = o + radius_m * Eigen::Vector2f(std::cos(pose.yaw()), std::sin(pose.yaw()));
  cv::line(canvas_->img, canvas_->px(o), canvas_->px(tip), bgr(c), 2, cv::LINE_AA);
}

void TopView::drawText(const std::string& text, const Eigen::Vector2f& at, Color c) {
  cv::putText(canvas_->img, text, canvas_->px(at), cv::FONT_HERSHEY_SIMPLEX, 0.45, bgr(c), 1,
              cv::LINE_AA);
}

void TopView::drawLegend(const std::string& text) {
  int y = 18;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = text.find('\n', start);
    const std::string line = text.substr(start, end == std::string::npos ? end : end - start);
    cv::putText(canvas_->img, line, {8, y}, cv::FONT_HERSHEY_SIMPLEX, 0.5, bgr(kBlack), 1, cv::LINE_AA);
    y += 18;
    if (end == std::string::npos) break;
    start = end + 1;
  }
}

void TopView::drawScaleBar() {
  const float metres = canvas_->bounds.sizes().x() > 20.f ? 5.f : 1.f;
  const int x0 = 10, y0 = canvas_->img.rows - 10;
  const int x1 = x0 + static_cast<int>(metres * canvas_->scale);
  cv::line(canvas_->img, {x0, y0}, {x1, y0}, bgr(kBlack), 2);
  cv::putText(canvas_->img, std::to_string(static_cast<int>(metres)) + " m", {x0, y0 - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
              bgr(kBlack), 1, cv::LINE_AA);
}

void TopView::save(const std::string& png_path) const { writePng(canvas_->img, png_path); }

}  // namespace polyloc::viz
