#include <polyloc/io/recording_grid.hpp>
#include <polyloc/io/message_pose.hpp>

#include <algorithm>
#include <optional>

namespace polyloc {
namespace {

const char* reason(ScanMapper::Added a) {
  switch (a) {
    case ScanMapper::Added::Used: return "used";
    case ScanMapper::Added::BadPose: return "bad_pose";
    case ScanMapper::Added::BadGeometry: return "bad_geometry";
    case ScanMapper::Added::NoBeams: return "no_valid_ranges";
    case ScanMapper::Added::TooLarge: return "too_large";
  }
  return "unknown";
}

}  // namespace

OccupancyGrid gridFromRecording(RecordingReader& reader, const std::vector<std::string>& scan_topics,
                                const ScanMapperConfig& config, RecordingGridStats* stats, const ScanSelection& select) {
  RecordingGridStats local;
  RecordingGridStats& st = stats ? *stats : local;
  ScanMapper mapper(config);
  // The scan of each topic still waiting for its pose; a second scan first means none came.
  std::map<std::string, std::optional<msg::LaserScan>> waiting;
  std::map<std::string, std::string> scan_of_pose;  // "<topic>_pose" -> topic
  std::map<std::string, size_t> number;             // scans with a pose so far, per topic
  for (const auto& t : scan_topics) waiting[t], scan_of_pose[t + "_pose"] = t;

  RecordedMessage m;
  while (reader.next(m)) {
    if (const auto* scan = std::get_if<msg::LaserScan>(&m.message)) {
      auto it = waiting.find(m.topic);
      if (it == waiting.end()) continue;
      if (it->second) ++st.skipped["no_pose"];
      it->second = std::move(*scan);
      continue;
    }
    const auto* pose = std::get_if<msg::PoseStamped>(&m.message);
    if (!pose) continue;
    auto p = scan_of_pose.find(m.topic);
    if (p == scan_of_pose.end()) continue;
    auto& s = waiting[p->second];
    if (!s) continue;  // a pose without its scan: nothing to place
    if (number[p->second]++ % std::max<size_t>(select.every, 1) != select.offset) {
      ++st.skipped["not_selected"];
      s.reset();
      continue;
    }
    const Pose laser = fromMsgPose(pose->pose);
    const auto added = mapper.add(laser.x(), laser.y(), laser.yaw(), s->ranges.data(), s->ranges.size(), s->angle_min,
                                  s->angle_increment, s->range_min, s->range_max);
    if (added == ScanMapper::Added::Used) ++st.scans_used, st.laser_path.push_back({float(laser.x()), float(laser.y())});
    else ++st.skipped[reason(added)];
    s.reset();
  }
  for (const auto& [topic, s] : waiting)
    if (s) ++st.skipped["no_pose"];
  return mapper.grid();
}

}  // namespace polyloc
