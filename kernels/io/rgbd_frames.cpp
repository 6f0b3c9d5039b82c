#include "rgbd_frames.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/io/message_pose.hpp>

#include <fmt/core.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

namespace polyloc {

RgbdIntrinsics loadIntrinsics(const std::string& yaml_file, RgbdIntrinsics k) {
  ConfigMap m = ConfigMap::load(yaml_file);
  const char* pinhole[] = {"fx", "fy", "cx", "cy"};
  int given = 0;
  for (const char* key : pinhole) given += m.has(key);
  if (given != 0 && given != 4) m.fail("the intrinsics need all of fx, fy, cx, cy (pixels) or none");
  if (given) {
    k.fx = m.getDouble("fx", k.fx, 1e-3, 1e6);
    k.fy = m.getDouble("fy", k.fy, 1e-3, 1e6);
    k.cx = m.getDouble("cx", k.cx, -0.5, 4096);
    k.cy = m.getDouble("cy", k.cy, -0.5, 4096);
  }
  k.depth_scale = m.getDouble("depth_scale", k.depth_scale, 1e-3, 1e9);
  k.rate_hz = m.getDouble("rate_hz", k.rate_hz, 1e-3, 1e4);
  m.finish();
  k.source = yaml_file;
  return k;
}

namespace io_detail {

RgbdIntrinsics chooseIntrinsics(const std::string& dir, const std::string& file, RgbdIntrinsics layout, ReadStats& stats) {
  namespace fs = std::filesystem;
  std::string path = file;
  std::error_code ec;
  if (path.empty() && fs::is_regular_file(fs::path(dir) / "intrinsics.yaml", ec))
    path = (fs::path(dir) / "intrinsics.yaml").string();
  RgbdIntrinsics k = path.empty() ? layout : loadIntrinsics(path, layout);
  stats.note(fmt::format("{}: depth camera fx {:g} fy {:g} cx {:g} cy {:g} px, {:g} units per metre (from {})", dir,
                         k.fx, k.fy, k.cx, k.cy, k.depth_scale, k.source));
  return k;
}

RgbdFrameReader::RgbdFrameReader(std::string name, std::string format, std::vector<RgbdFrame> frames,
                                 const RgbdIntrinsics& k, ReadStats stats)
    : name_(std::move(name)), format_(std::move(format)), frames_(std::move(frames)), k_(k), stats_(std::move(stats)) {
  // The size comes from the first image that decodes; the intrinsics must fit it.
  for (const RgbdFrame& f : frames_) {
    const cv::Mat img = cv::imread(f.depth_path, cv::IMREAD_UNCHANGED);
    if (img.empty() || img.type() != CV_16UC1) continue;
    width_ = img.cols, height_ = img.rows;
    break;
  }
  if (width_ == 0) throw IoError(fmt::format("{}: none of its {} depth images is a readable 16-bit PNG", name_, frames_.size()));
  if (k_.cx < -0.5 || k_.cx > width_ - 0.5 || k_.cy < -0.5 || k_.cy > height_ - 0.5)
    throw IoError(fmt::format("{}: principal point ({:g}, {:g}) lies outside the {}x{} images (intrinsics from {})", name_,
                              k_.cx, k_.cy, width_, height_, k_.source));
}

std::vector<TopicInfo> RgbdFrameReader::topics() {
  TopicInfo info{kRgbdInfoTopic, "sensor_msgs/msg/CameraInfo"}, image{kRgbdImageTopic, "sensor_msgs/msg/Image"},
      truth{"/ground_truth", "geometry_msgs/msg/PoseStamped"};
  for (const RgbdFrame& f : frames_)
    for (TopicInfo* t : {&info, &image, f.world_T_optical ? &truth : nullptr}) {
      if (!t) continue;
      if (t->count++ == 0) t->first_ns = f.stamp_ns;
      t->last_ns = f.stamp_ns;
    }
  std::vector<TopicInfo> out{info, image};
  if (truth.count) out.push_back(truth);
  return out;
}

std::optional<msg::Image> RgbdFrameReader::decode(const RgbdFrame& f, size_t index) {
  const cv::Mat img = cv::imread(f.depth_path, cv::IMREAD_UNCHANGED);
  auto reject = [&](const std::string& why) {
    stats_.warn(fmt::format("{}: frame {} ({}): {}: frame skipped", name_, index, f.depth_path, why));
    return std::nullopt;
  };
  if (img.empty()) return reject("not a readable image");
  if (img.type() != CV_16UC1) return reject(fmt::format("{} channel(s) of {} bytes, not 16-bit depth", img.channels(), img.elemSize1()));
  if (img.cols != width_ || img.rows != height_)
    return reject(fmt::format("{}x{} pixels, the first frame has {}x{}", img.cols, img.rows, width_, height_));
  msg::Image out;
  out.header.stamp = msg::fromNs(f.stamp_ns);
  out.header.frame_id = "camera_depth_optical_frame";
  out.width = uint32_t(width_), out.height = uint32_t(height_);
  out.encoding = "32FC1";
  out.step = out.width * 4;
  out.data.resize(size_t(out.step) * out.height);
  const float scale = float(1.0 / k_.depth_scale), nan = std::numeric_limits<float>::quiet_NaN();
  float* dst = reinterpret_cast<float*>(out.data.data());
  for (int v = 0; v < height_; ++v) {
    const uint16_t* row = img.ptr<uint16_t>(v);
    for (int u = 0; u < width_; ++u) {
      const uint16_t d = row[u];
      // 0: no return; 65535: 7-Scenes' and Kinect drivers' "invalid".
      *dst++ = d == 0 || d == 65535 ? nan : float(d) * scale;
    }
  }
  return out;
}

bool RgbdFrameReader::next(RecordedMessage& out) {
  while (pending_.empty() && next_frame_ < frames_.size()) {
    const size_t index = next_frame_++;
    const RgbdFrame& f = frames_[index];
    if (std::optional<msg::Image> img = decode(f, index)) {
      msg::CameraInfo info;
      info.header = img->header;
      info.width = img->width, info.height = img->height;
      info.d = {0, 0, 0, 0, 0};
      info.k = {k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1};
      info.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      info.p = {k_.fx, 0, k_.cx, 0, 0, k_.fy, k_.cy, 0, 0, 0, 1, 0};
      pending_.push_back({kRgbdInfoTopic, f.stamp_ns, f.stamp_ns, std::move(info)});
      pending_.push_back({kRgbdImageTopic, f.stamp_ns, f.stamp_ns, std::move(*img)});
    }
    if (f.world_T_optical) {
      msg::PoseStamped p;
      p.header.stamp = msg::fromNs(f.stamp_ns);
      p.header.frame_id = "map";
      p.pose = toMsgPose(*f.world_T_optical * opticalFromBody());
      pending_.push_back({"/ground_truth", f.stamp_ns, f.stamp_ns, std::move(p)});
    }
  }
  if (pending_.empty()) return false;
  out = std::move(pending_.front());
  pending_.pop_front();
  ++stats_.messages;
  return true;
}

}  // namespace io_detail
}  // namespace polyloc
