// Helpers of the simulator tests: an in-memory RecordingWriter, a byte dump of messages for
// byte-identical comparisons (independent of the CDR/MCAP code), small scenarios in code.
#pragma once

#include "fixtures.hpp"

#include <polyloc/io/recording.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/sim/simulator.hpp>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace polyloc::test {

class CaptureWriter final : public RecordingWriter {
 public:
  struct Entry {
    std::string topic;
    int64_t stamp;
    msg::Message message;
  };
  void write(const std::string& topic, int64_t t, const msg::Message& m) override { entries.push_back({topic, t, m}); }
  void close() override {}
  std::vector<const Entry*> on(const std::string& topic) const {
    std::vector<const Entry*> out;
    for (const auto& e : entries)
      if (e.topic == topic) out.push_back(&e);
    return out;
  }
  std::vector<Entry> entries;
};

// The bundled lab tour simulated for `seconds`: its messages, and the simulator for the truth.
struct LabTour {
  Scenario scenario;
  std::unique_ptr<Simulator> sim;
  CaptureWriter rec;
  explicit LabTour(double seconds) : scenario(loadScenario(std::string(POLYLOC_SOURCE_DIR) + "/maps/scenarios/lab_tour.yaml")) {
    scenario.duration = seconds;
    sim = std::make_unique<Simulator>(scenario, loadScenarioMap(scenario));
    sim->run(rec);
  }
};

// Every field of a message as bytes, in declaration order.
class Dump {
 public:
  std::string bytes;
  template <class T>
  void pod(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof(T)); }
  void str(const std::string& s) { pod(s.size()), bytes += s; }
  template <class T>
  void vec(const std::vector<T>& v) { pod(v.size()), bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)); }
  void header(const msg::Header& h) { pod(h.stamp.sec), pod(h.stamp.nanosec), str(h.frame_id); }
  void pose(const msg::Pose& p) {
    for (double d : {p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w}) pod(d);
  }
  void operator()(const msg::LaserScan& s) {
    header(s.header);
    for (float f : {s.angle_min, s.angle_max, s.angle_increment, s.time_increment, s.scan_time, s.range_min, s.range_max}) pod(f);
    vec(s.ranges), vec(s.intensities);
  }
  void operator()(const msg::PointCloud2& p) {
    header(p.header), pod(p.height), pod(p.width), pod(p.point_step), pod(p.row_step), vec(p.data), pod(p.is_dense);
    for (const auto& f : p.fields) str(f.name), pod(f.offset), pod(f.datatype), pod(f.count);
  }
  void operator()(const msg::Image& i) {
    header(i.header), pod(i.height), pod(i.width), str(i.encoding), pod(i.is_bigendian), pod(i.step), vec(i.data);
  }
  void operator()(const msg::CameraInfo& c) {
    header(c.header), pod(c.height), pod(c.width), str(c.distortion_model), vec(c.d), pod(c.k), pod(c.r), pod(c.p);
  }
  void operator()(const msg::Odometry& o) {
    header(o.header), str(o.child_frame_id), pose(o.pose.pose), pod(o.pose.covariance);
    const auto& t = o.twist.twist;
    for (double d : {t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z}) pod(d);
    pod(o.twist.covariance);
  }
  void operator()(const msg::TFMessage& m) {
    for (const auto& t : m.transforms) {
      header(t.header), str(t.child_frame_id);
      const auto& x = t.transform;
      for (double d : {x.translation.x, x.translation.y, x.translation.z, x.rotation.x, x.rotation.y, x.rotation.z, x.rotation.w}) pod(d);
    }
  }
  void operator()(const msg::PoseStamped& p) { header(p.header), pose(p.pose); }
  void operator()(const msg::PoseWithCovarianceStamped& p) { header(p.header), pose(p.pose.pose), pod(p.pose.covariance); }
  void operator()(const msg::TrackArray& a) {
    header(a.header);
    for (const auto& t : a.tracks) pod(t.id), pod(t.status), pod(t.x), pod(t.y), pod(t.vx), pod(t.vy), pod(t.covariance);
  }
};

inline std::string dumpAll(const CaptureWriter& w) {
  Dump d;
  for (const auto& e : w.entries) {
    d.str(e.topic), d.pod(e.stamp);
    std::visit(d, e.message);
  }
  return d.bytes;
}

// A scenario in the closed box room of fixtures.hpp: a robot standing (one waypoint) or driving,
// one sensor; noise settings are the caller's.
inline Scenario roomScenario(const Sensor& sensor, const std::string& preset, double duration) {
  Scenario s;
  s.config.robot.radius = 0.25;
  s.config.rig.name = "test";
  s.config.rig.add(sensor, preset);
  s.noise.sensors = defaultSensorNoise(s.config.rig);
  s.route.waypoints.resize(1);  // standing at the origin
  s.route.start_pause = 0.0;
  s.duration = duration;
  return s;
}

}  // namespace polyloc::test
