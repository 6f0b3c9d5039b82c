#include "reloc/recorded_rig.hpp"
#include "reloc/topic_router.hpp"

#include <polyloc/io/recorded_geometry.hpp>

#include <fmt/core.h>

#include <map>
#include <stdexcept>

namespace polyloc::reloc {

bool needsRecordedRig(const PolylocConfig& c) {
  if (c.rig_from_recording) return true;
  for (const Sensor& s : c.rig.sensors)
    if (const auto* p = std::get_if<PlanarScannerSpec>(&s.spec); p && p->from_recording) return true;
  return false;
}

std::string sensorNameForTopic(const std::string& topic) {
  std::string name = topic;
  if (name.starts_with("/scan/")) name = name.substr(6);
  else if (name.starts_with("/")) name = name.substr(1);
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

std::string depthSensorNameForTopic(const std::string& topic) {
  if (topic.starts_with("/depth/") && topic.ends_with("/image") && topic.size() > 13)
    return topic.substr(7, topic.size() - 13);
  const size_t slash = topic.rfind('/');
  return sensorNameForTopic(slash == std::string::npos || slash == 0 ? topic : topic.substr(0, slash));
}

namespace {

std::string topicNamespace(const std::string& topic) {
  const size_t slash = topic.rfind('/');
  return slash == std::string::npos ? std::string{} : topic.substr(0, slash);
}

// A depth camera from its CameraInfo (K, size) at the base's origin, looking along base x.
Sensor depthSensorFrom(const std::string& image_topic, const msg::CameraInfo& info, const msg::Image& first, double rate,
                       const std::string& name) {
  if (info.width != first.width || info.height != first.height)
    throw std::runtime_error(fmt::format("{}: {}: camera info says {}x{}, the first image is {}x{}", name, image_topic,
                                         info.width, info.height, first.width, first.height));
  Sensor s;
  s.name = depthSensorNameForTopic(image_topic);
  try {
    s.spec = depthCameraFromIntrinsics(int(info.width), int(info.height), info.k[0], info.k[4], info.k[2], info.k[5],
                                       kRecordedDepthRange[0], kRecordedDepthRange[1], rate);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: {}: {}", name, image_topic, e.what()));
  }
  return s;
}

}  // namespace

Rig recordedRig(const PolylocConfig& cfg, RecordingReader& reader, const std::string& name, std::vector<std::string>* notes) {
  // Scan topics and their rates, depth image candidates (an Image beside a CameraInfo in one
  // namespace), then the first message of each.
  std::map<std::string, double> rates, image_rates;
  std::map<std::string, std::string> info_topics;  // namespace -> camera info topic
  for (const TopicInfo& t : reader.topics()) {
    if (t.name.starts_with("/ground_truth")) continue;
    if (t.type == "sensor_msgs/msg/LaserScan") rates[t.name] = t.rateHz();
    if (t.type == "sensor_msgs/msg/CameraInfo") info_topics[topicNamespace(t.name)] = t.name;
  }
  if (cfg.rig_from_recording)
    for (const TopicInfo& t : reader.topics())
      if (t.type == "sensor_msgs/msg/Image" && info_topics.count(topicNamespace(t.name))) image_rates[t.name] = t.rateHz();
  if (rates.empty() && image_rates.empty())
    throw std::runtime_error(fmt::format("{}: no LaserScan topic (nor a depth image beside its camera info) to make a rig from", name));
  std::map<std::string, msg::LaserScan> first;
  std::map<std::string, msg::Image> first_image;
  std::map<std::string, msg::CameraInfo> first_info;
  RecordedMessage m;
  auto complete = [&] {
    return first.size() == rates.size() && first_image.size() == image_rates.size() &&
           (image_rates.empty() || first_info.size() == info_topics.size());
  };
  while (!complete() && reader.next(m)) {
    if (const auto* s = std::get_if<msg::LaserScan>(&m.message); s && rates.count(m.topic) && !first.count(m.topic))
      first.emplace(m.topic, *s);
    if (const auto* i = std::get_if<msg::Image>(&m.message); i && image_rates.count(m.topic) && !first_image.count(m.topic)) {
      msg::Image head = *i;
      head.data.clear();  // the size and encoding are what is needed
      first_image.emplace(m.topic, std::move(head));
    }
    if (const auto* c = std::get_if<msg::CameraInfo>(&m.message); c && !first_info.count(m.topic))
      first_info.emplace(m.topic, *c);
  }
  auto specOf = [&](const std::string& topic, const std::string& sensor) {
    auto it = first.find(topic);
    if (it == first.end())
      throw std::runtime_error(fmt::format("{}: sensor '{}' takes its geometry from the recording, but {} has no scan",
                                           name, sensor, topic));
    try {
      return planarSpecFromScan(it->second, rates[topic]);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("{}: {}: {}", name, topic, e.what()));
    }
  };
  auto note = [&](const std::string& s) { if (notes) notes->push_back(s); };

  if (cfg.rig_from_recording) {
    Rig rig;
    rig.name = "recorded";
    for (const auto& [topic, rate] : rates) {
      Sensor s;
      s.name = sensorNameForTopic(topic);
      s.spec = specOf(topic, s.name);
      // CARMEN's rear laser looks backwards; every other scanner is taken to look ahead.
      s.mount = Pose::fromXYZRPY(0, 0, kRecordedHeight, 0, 0, topic == "/rear_laser" ? M_PI : 0);
      note(fmt::format("rig from the recording: sensor '{}' on {}: {}, range {:g}..{:g} m, mount z {:g} m{}", s.name,
                       topic, describeGeometry(std::get<PlanarScannerSpec>(s.spec)), std::get<PlanarScannerSpec>(s.spec).range_min,
                       std::get<PlanarScannerSpec>(s.spec).range_max, kRecordedHeight, topic == "/rear_laser" ? ", yaw 180 deg" : ""));
      rig.add(std::move(s), "recorded");
    }
    for (const auto& [topic, rate] : image_rates) {
      auto img = first_image.find(topic);
      auto info = first_info.find(info_topics[topicNamespace(topic)]);
      if (img == first_image.end() || info == first_info.end()) continue;
      if (img->second.encoding != "32FC1" && img->second.encoding != "16UC1") continue;  // colour, IR: no depth
      Sensor s = depthSensorFrom(topic, info->second, img->second, rate, name);
      const auto& c = std::get<DepthCameraSpec>(s.spec);
      note(fmt::format("rig from the recording: depth camera '{}' on {}: {}x{} px, fx {:g} fy {:g} cx {:g} cy {:g} ({}), "
                       "range {:g}..{:g} m, at the base's origin",
                       s.name, topic, c.width, c.height, c.fx(), c.fy(), info->second.k[2], info->second.k[5],
                       info->first, c.range_min, c.range_max));
      rig.add(std::move(s), "recorded");
    }
    if (rig.sensors.empty())
      throw std::runtime_error(fmt::format("{}: no LaserScan and no 16UC1/32FC1 depth image to make a rig from", name));
    return rig;
  }
  Rig rig = cfg.rig;
  for (Sensor& s : rig.sensors) {
    auto* p = std::get_if<PlanarScannerSpec>(&s.spec);
    if (!p || !p->from_recording) continue;
    // The topic the TopicRouter routes to this sensor.
    const TopicRouter router(cfg.rig, {});
    std::string topic;
    for (const auto& [t, rate] : rates)
      if (router.sensorForScan(t) == cfg.rig.find(s.name)) topic = t;
    if (topic.empty())
      throw std::runtime_error(fmt::format("{}: sensor '{}' (preset recorded) has no LaserScan topic of its name", name, s.name));
    *p = specOf(topic, s.name);
    note(fmt::format("sensor '{}' takes its geometry from {}: {}", s.name, topic, describeGeometry(*p)));
  }
  return rig;
}

void completeRecordedRig(PolylocConfig& config, RecordingReader& reader, const std::string& name,
                         const std::function<void(const std::string&)>& log) {
  if (!needsRecordedRig(config)) return;
  std::vector<std::string> notes;
  config.rig = recordedRig(config, reader, name, &notes);
  config.rig_from_recording = false;
  if (log)
    for (const auto& n : notes) log(n);
}

}  // namespace polyloc::reloc
