#include <polyloc/fusion/posed_frames.hpp>
#include <polyloc/io/depth_image.hpp>
#include <polyloc/io/message_pose.hpp>

#include <fmt/core.h>

#include <charconv>
#include <deque>
#include <optional>
#include <stdexcept>

namespace polyloc {
namespace {

constexpr int64_t kMaxPoseGap = 50'000'000;  // ns: as the TUM reader interpolates its truth
constexpr size_t kMaxPending = 8;            // frames waiting for a pose after them (memory bound)

std::string topicNamespace(const std::string& topic) {
  const size_t slash = topic.rfind('/');
  return slash == std::string::npos ? std::string{} : topic.substr(0, slash);
}

struct Pending {
  int64_t index = 0, stamp = 0;
  std::vector<float> depth;
};

}  // namespace

bool FrameSelection::picks(int64_t i) const {
  if (i < first || (last >= 0 && i > last) || (i - first) % step != 0) return false;
  return parity == Parity::All || (i % 2 == 0) == (parity == Parity::Even);
}

FrameSelection FrameSelection::parse(const std::string& text) {
  FrameSelection s;
  if (text == "all") return s;
  if (text == "even") return s.parity = Parity::Even, s;
  if (text == "odd") return s.parity = Parity::Odd, s;
  auto bad = [&] { return std::invalid_argument(fmt::format("frames '{}': all, even, odd or FIRST:LAST[:STEP]", text)); };
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t c; (c = text.find(':', start)) != std::string::npos; start = c + 1) parts.push_back(text.substr(start, c - start));
  parts.push_back(text.substr(start));
  if (parts.size() < 2 || parts.size() > 3) throw bad();
  auto number = [&](const std::string& p, int64_t def) {
    if (p.empty()) return def;
    int64_t v = 0;
    auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), v);
    if (ec != std::errc() || end != p.data() + p.size() || v < 0) throw bad();
    return v;
  };
  s.first = number(parts[0], 0);
  s.last = number(parts[1], -1);
  s.step = parts.size() == 3 ? number(parts[2], 1) : 1;
  if (s.step < 1 || (s.last >= 0 && s.last < s.first)) throw bad();
  return s;
}

void forEachPosedFrame(RecordingReader& reader, const std::string& name, const FrameSelection& selection,
                       double range_min, double range_max, PosedFrameStats& st,
                       const std::function<void(const PosedFrame&)>& deliver, const std::function<void(double)>& progress) {
  // The depth topic: an Image beside a CameraInfo in its namespace (the first by name).
  std::string info_topic;
  const std::vector<TopicInfo> topics = reader.topics();
  for (const TopicInfo& t : topics)
    if (t.type == "sensor_msgs/msg/CameraInfo")
      for (const TopicInfo& i : topics)
        if (i.type == "sensor_msgs/msg/Image" && topicNamespace(i.name) == topicNamespace(t.name) &&
            (st.image_topic.empty() || i.name < st.image_topic))
          st.image_topic = i.name, info_topic = t.name;
  if (st.image_topic.empty()) throw std::runtime_error(fmt::format("{}: no depth Image beside a CameraInfo", name));
  const RecordingSpan span = spanOf(topics);

  bool have_camera = false;
  std::deque<Pending> pending;
  std::optional<std::pair<int64_t, Pose>> prev_truth, last_truth;
  auto skip = [&](const Pending& f, const std::string& reason) {
    ++st.reasons[reason];
    if (st.warnings.size() < 20) st.warnings.push_back(fmt::format("{}: frame {}: {}", name, f.index, reason));
  };
  auto give = [&](const Pending& f, const Pose& pose) {
    ++st.delivered;
    deliver(PosedFrame{f.index, f.stamp, f.depth, pose});
  };
  // A frame's pose from the two truth samples around it, if they are close enough.
  auto poseAt = [&](int64_t t) -> std::optional<Pose> {
    if (last_truth && last_truth->first == t) return last_truth->second;
    if (!prev_truth || !last_truth || t < prev_truth->first || t > last_truth->first) return std::nullopt;
    if (t - prev_truth->first > kMaxPoseGap || last_truth->first - t > kMaxPoseGap) return std::nullopt;
    const double s = double(t - prev_truth->first) / double(last_truth->first - prev_truth->first);
    return Pose::interpolate(prev_truth->second, last_truth->second, s);
  };
  auto resolve = [&](const Pending& f) {
    if (auto p = poseAt(f.stamp)) give(f, *p);
    else ++st.without_pose, skip(f, "no /ground_truth pose within 50 ms of its stamp");
  };

  RecordedMessage m;
  uint64_t read = 0;
  int64_t index = 0;
  while (reader.next(m)) {
    if (progress && span.messages && ++read % 64 == 0) progress(double(read) / double(span.messages));
    if (m.topic == info_topic && !have_camera) {
      const auto* info = std::get_if<msg::CameraInfo>(&m.message);
      if (!info) continue;
      try {
        st.camera = depthCameraFromIntrinsics(int(info->width), int(info->height), info->k[0], info->k[4], info->k[2],
                                              info->k[5], range_min, range_max, 30.0);
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(fmt::format("{}: {}: {}", name, info_topic, e.what()));
      }
      have_camera = true;
    } else if (m.topic == st.image_topic) {
      const auto* img = std::get_if<msg::Image>(&m.message);
      if (!img) continue;
      Pending f{index++, msg::toNs(img->header.stamp), {}};
      if (f.stamp == 0) f.stamp = m.log_time_ns;
      ++st.images;
      if (!selection.picks(f.index)) continue;
      ++st.selected;
      std::string bad = have_camera ? depthImageToMetres(*img, f.depth) : "no camera info on " + info_topic + " before it";
      if (bad.empty() && (int(img->width) != st.camera.width || int(img->height) != st.camera.height))
        bad = fmt::format("{}x{} pixels, the camera info says {}x{}", img->width, img->height, st.camera.width,
                          st.camera.height);
      if (!bad.empty()) {
        ++st.bad_images, skip(f, bad);
        continue;
      }
      if (last_truth && f.stamp <= last_truth->first) {  // its pose came first
        resolve(f);
        continue;
      }
      pending.push_back(std::move(f));
      if (pending.size() > kMaxPending) resolve(pending.front()), pending.pop_front();
    } else if (m.topic == "/ground_truth") {
      const auto* p = std::get_if<msg::PoseStamped>(&m.message);
      if (!p) continue;
      const int64_t t = msg::toNs(p->header.stamp) ? msg::toNs(p->header.stamp) : m.log_time_ns;
      if (last_truth && t <= last_truth->first) continue;  // not increasing: keep the earlier
      prev_truth = last_truth;
      last_truth = {t, fromMsgPose(p->pose)};
      while (!pending.empty() && pending.front().stamp <= t) resolve(pending.front()), pending.pop_front();
    }
  }
  for (const Pending& f : pending) resolve(f);
  if (progress) progress(1.0);
}

}  // namespace polyloc
