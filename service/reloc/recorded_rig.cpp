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

Rig recordedRig(const PolylocConfig& cfg, RecordingReader& reader, const std::string& name, std::vector<std::string>* notes) {
  // Scan topics and their rates, then the first scan of each.
  std::map<std::string, double> rates;
  for (const TopicInfo& t : reader.topics())
    if (t.type == "sensor_msgs/msg/LaserScan" && !t.name.starts_with("/ground_truth")) rates[t.name] = t.rateHz();
  if (rates.empty()) throw std::runtime_error(fmt::format("{}: no LaserScan topic to make a rig from", name));
  std::map<std::string, msg::LaserScan> first;
  RecordedMessage m;
  while (first.size() < rates.size() && reader.next(m))
    if (const auto* s = std::get_if<msg::LaserScan>(&m.message); s && rates.count(m.topic) && !first.count(m.topic))
      first.emplace(m.topic, *s);
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
