#include <polyloc/eval/real_log.hpp>
#include <polyloc/io/message_pose.hpp>

#include <fmt/core.h>

#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

namespace polyloc {

RealLog readRealLog(const std::string& path, const std::string& topic) {
  auto reader = openRecording(path);
  RealLog log;
  log.path = path;
  // Every laser topic's scans with poses; the chosen topic is decided at the end.
  std::map<std::string, std::vector<LoggedScan>> by_topic;
  std::map<std::string, std::optional<LoggedScan>> waiting;  // scan topic -> scan awaiting its pose
  std::map<std::string, uint64_t> without_pose;
  RecordedMessage m;
  while (reader->next(m)) {
    const uint64_t order = log.messages++;
    if (const auto* s = std::get_if<msg::LaserScan>(&m.message)) {
      auto& w = waiting[m.topic];
      if (w) ++without_pose[m.topic];
      const int64_t t = msg::toNs(s->header.stamp) ? msg::toNs(s->header.stamp) : m.log_time_ns;
      w = LoggedScan{t, order, *s, Pose()};
    } else if (const auto* p = std::get_if<msg::PoseStamped>(&m.message)) {
      if (!m.topic.ends_with("_pose")) continue;
      const std::string scan_topic = m.topic.substr(0, m.topic.size() - 5);
      auto it = waiting.find(scan_topic);
      if (it == waiting.end() || !it->second) continue;
      LoggedScan s = std::move(*it->second);
      it->second.reset();
      s.pose = fromMsgPose(p->pose);
      if (s.pose.translation().allFinite()) by_topic[scan_topic].push_back(std::move(s));
      else ++without_pose[scan_topic];
    } else if (const auto* o = std::get_if<msg::Odometry>(&m.message)) {
      if (m.topic != "/odom") continue;
      log.odometry.push_back({msg::toNs(o->header.stamp), order, fromMsgPose(o->pose.pose)});
    }
  }
  log.stats = reader->stats();
  for (auto& [t, w] : waiting)
    if (w) ++without_pose[t];
  if (!topic.empty()) {
    log.topic = topic;
  } else {
    // The first laser topic in file order that has poses.
    uint64_t first = UINT64_MAX;
    for (const auto& [t, scans] : by_topic)
      if (!scans.empty() && scans.front().order < first) first = scans.front().order, log.topic = t;
  }
  auto it = by_topic.find(log.topic);
  if (it == by_topic.end() || it->second.empty())
    throw std::runtime_error(fmt::format("{}: no laser scan with a logged pose{}", path,
                                         topic.empty() ? std::string() : " on " + topic));
  log.scans = std::move(it->second);
  log.scans_without_pose = without_pose[log.topic];
  return log;
}

}  // namespace polyloc
