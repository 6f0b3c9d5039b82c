// DepthFilter: the pipeline of stages (stages.hpp) and the points in the base frame.
#include <polyloc/depth/filter.hpp>

#include "stages.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace polyloc {

const char* depthRejectName(DepthReject r) {
  switch (r) {
    case DepthReject::kKept: return "kept";
    case DepthReject::kNoMeasurement: return "no_measurement";
    case DepthReject::kRange: return "range";
    case DepthReject::kAmplitude: return "amplitude";
    case DepthReject::kJumpEdge: return "jump_edge";
    case DepthReject::kConfidence: return "confidence";
  }
  return "unknown";
}

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("depth filter: " + what);
}

}  // namespace

DepthFilter::DepthFilter(const DepthCameraSpec& camera, const Pose& base_T_sensor, DepthFilterConfig config)
    : camera_(camera), base_T_sensor_(base_T_sensor), config_(std::move(config)) {
  check(camera.width > 0 && camera.height > 0, "camera size must be positive");
  const DepthFilterConfig& c = config_;
  check(c.jump_edge.neighbours == 4 || c.jump_edge.neighbours == 8, "jump_edge.neighbours must be 4 or 8");
  check(c.jump_edge.mode == "between" || c.jump_edge.mode == "any", "jump_edge.mode must be between or any");
  check(c.confidence.iterations >= 0, "confidence.iterations must be >= 0");
  check(c.confidence.sigma > 0 && c.confidence.noise > 0 && c.confidence.sigma_c > 0,
        "confidence.sigma, noise and sigma_c must be > 0");
  check(c.confidence.prediction == "slope" || c.confidence.prediction == "neighbour",
        "confidence.prediction must be slope or neighbour");
  check(c.confidence.reach >= 1 && c.confidence.reach <= 16, "confidence.reach must be 1..16");
  const std::string& col = c.confidence.colour;
  check(col == "auto" || col == "rgb" || col == "amplitude" || col == "none",
        "confidence.colour must be auto, rgb, amplitude or none");
  const std::string& m = c.smoothing.method;
  check(m == "none" || m == "median" || m == "bilateral", "smoothing.method must be none, median or bilateral");
  if (m == "median") check(c.smoothing.size == 3 || c.smoothing.size == 5, "smoothing.size must be 3 or 5 for median");
  if (m == "bilateral") check(c.smoothing.size >= 1 && c.smoothing.size <= 15, "smoothing.size must be 1..15 for bilateral");
  range_min_ = static_cast<float>(c.validity.range_min.value_or(camera.range_min));
  range_max_ = static_cast<float>(c.validity.range_max.value_or(camera.range_max));

  // Pixel (u, v) centre in the optical frame: ((u + 0.5 - cx) / fx, (v + 0.5 - cy) / fy, 1)
  // (DepthCameraSpec::beams); in the body frame (x forward, y left, z up) that is (1, -x, -y).
  const size_t n = camera.numBeams();
  for (auto* v : {&xn_, &yn_, &range_per_depth_, &qx_, &qy_, &qz_}) v->resize(n);
  const Eigen::Matrix3d R = base_T_sensor.rotation().toRotationMatrix();
  const double ifx = 1.0 / camera.fx(), ify = 1.0 / camera.fy();
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const size_t i = size_t(v) * camera.width + u;
      const double x = (u + 0.5 - camera.cx()) * ifx, y = (v + 0.5 - camera.cy()) * ify;
      xn_[i] = float(x), yn_[i] = float(y);
      range_per_depth_[i] = float(std::sqrt(x * x + y * y + 1.0));
      const Eigen::Vector3d q = R * Eigen::Vector3d(1.0, -x, -y);
      qx_[i] = float(q.x()), qy_[i] = float(q.y()), qz_[i] = float(q.z());
    }
}

void DepthFilter::apply(const DepthFrameView& frame, DepthFilterResult& out) const {
  check(frame.depth != nullptr, "no depth buffer");
  check(frame.width == camera_.width && frame.height == camera_.height,
        "frame is " + std::to_string(frame.width) + "x" + std::to_string(frame.height) + ", the camera " +
            std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
  const size_t n = camera_.numBeams();
  out.width = frame.width, out.height = frame.height;
  out.depth.resize(n);
  out.reason.resize(n);
  out.valid.resize(n);
  depth_detail::Work work{frame.width, frame.height, out.depth.data(), out.reason.data()};

  depth_detail::checkValidity(frame, config_.validity, range_min_, range_max_, range_per_depth_.data(), work);
  depth_detail::rejectJumpEdges(config_.jump_edge, xn_.data(), yn_.data(), work);
  depth_detail::rejectLowConfidence(config_.confidence, frame, work);
  depth_detail::smoothDepth(config_.smoothing, work);

  out.count.fill(0);
  out.x.clear(), out.y.clear(), out.z.clear(), out.pixel.clear();
  const Eigen::Vector3f t = base_T_sensor_.translation().cast<float>();
  for (size_t i = 0; i < n; ++i) {
    ++out.count[static_cast<size_t>(out.reason[i])];
    out.valid[i] = out.reason[i] == DepthReject::kKept;
    if (!out.valid[i]) continue;
    const float d = out.depth[i];
    out.x.push_back(t.x() + d * qx_[i]);
    out.y.push_back(t.y() + d * qy_[i]);
    out.z.push_back(t.z() + d * qz_[i]);
    out.pixel.push_back(static_cast<uint32_t>(i));
  }
}

void DepthFilter::applyBatch(std::span<const DepthFrameView> frames, std::span<DepthFilterResult> out) const {
  check(frames.size() == out.size(), "batch of " + std::to_string(frames.size()) + " frames but " +
                                         std::to_string(out.size()) + " results");
  // Checked up front: an exception out of the parallel loop would leave other results half done.
  for (const DepthFrameView& f : frames)
    check(f.depth && f.width == camera_.width && f.height == camera_.height, "a frame of the batch does not fit the camera");
  tbb::parallel_for(size_t(0), frames.size(), [&](size_t k) { apply(frames[k], out[k]); });
}

}  // namespace polyloc
