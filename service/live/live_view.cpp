#include "live/live_view.hpp"

#include "live/page.hpp"

#include <fmt/core.h>

#include <cmath>

namespace polyloc::live {
namespace {

ServerConfig serverConfig(const LiveConfig& c) {
  ServerConfig s;
  s.address = c.address, s.port = c.port, s.max_clients = c.max_clients;
  s.max_queue_bytes = size_t(c.max_queue_mib * double(1 << 20));
  s.stall_timeout_s = c.stall_timeout_s;
  s.max_pending = c.max_pending, s.handshake_timeout_s = c.handshake_timeout_s;
  s.max_subscriptions = c.max_subscriptions, s.max_client_rate = c.max_client_rate;
  s.page = livePage();
  return s;
}

}  // namespace

LiveView::LiveView(const LiveConfig& cfg, const Mesh& map, const Rig& rig, std::vector<std::string> inputs)
    : cfg_(cfg), rig_(rig), inputs_(std::move(inputs)), server_(serverConfig(cfg)) {
  ch_map_ = server_.addChannel(jsonChannel("/map", "foxglove.SceneUpdate", true));
  ch_slice_ = server_.addChannel(jsonChannel("/polyloc/map_slice", "polyloc.MapSlice", true));
  ch_tf_static_ = server_.addChannel(cdrChannel("/tf_static", "tf2_msgs/msg/TFMessage", true));
  ch_pose_ = server_.addChannel(cdrChannel("/pose", "geometry_msgs/msg/PoseWithCovarianceStamped"));
  ch_particles_ = server_.addChannel(cdrChannel("/particles", "sensor_msgs/msg/PointCloud2"));
  ch_tf_ = server_.addChannel(cdrChannel("/tf", "tf2_msgs/msg/TFMessage"));
  ch_vrs_ = server_.addChannel(cdrChannel("/vrs", "sensor_msgs/msg/LaserScan"));
  ch_tracks_ = server_.addChannel(cdrChannel("/tracks", "polyloc_msgs/msg/TrackArray"));
  ch_scan_.assign(rig.size(), 0), ch_depth_.assign(rig.size(), 0), last_depth_ns_.assign(rig.size(), INT64_MIN);
  beams_.resize(rig.size());
  for (size_t i = 0; i < rig.size(); ++i) {
    const Sensor& s = rig.sensors[i];
    if (std::holds_alternative<PlanarScannerSpec>(s.spec)) {
      ch_scan_[i] = server_.addChannel(cdrChannel("/scan/" + s.name, "sensor_msgs/msg/LaserScan"));
    } else if (std::holds_alternative<LidarSpec>(s.spec)) {
      ch_scan_[i] = server_.addChannel(cdrChannel("/points/" + s.name, "sensor_msgs/msg/PointCloud2"));
      beams_[i] = s.beams();
    } else if (std::holds_alternative<DepthCameraSpec>(s.spec))
      ch_depth_[i] = server_.addChannel(cdrChannel("/depth/" + s.name + "/points", "sensor_msgs/msg/PointCloud2"));
  }
  if (cfg.ground_truth) ch_truth_ = server_.addChannel(cdrChannel("/ground_truth", "geometry_msgs/msg/PoseStamped"));
  ch_health_ = server_.addChannel(jsonChannel("/polyloc/health", "polyloc.Health"));
  ch_topview_ = server_.addChannel(jsonChannel("/polyloc/topview", "polyloc.TopView"));
  server_.start();
  // Latched: kept by the server for every client that subscribes later.
  server_.publish(ch_map_, 0, sceneOfMesh(map));
  server_.publish(ch_slice_, 0, mapSliceJson(map, cfg.slice_height));
  server_.publish(ch_tf_static_, 0, tfStaticCdr(rig));
}

LiveView::~LiveView() { server_.stop(); }

bool LiveView::due(int64_t& last_ns, int64_t stamp_ns) const {
  // Data time, not wall time: a replay at 10x shows the same frames as one at 1x. At least a
  // period apart (poses at a jittered 100 ms then give 6 to 7 Hz, never more than the rate).
  if (last_ns != INT64_MIN && stamp_ns >= last_ns && double(stamp_ns - last_ns) < 1e9 / cfg_.rate_hz) return false;
  last_ns = stamp_ns;
  return true;
}

void LiveView::groundTruth(int64_t stamp_ns, const Pose& map_T_base) {
  if (ch_truth_ && server_.subscribed(ch_truth_)) server_.publish(ch_truth_, uint64_t(stamp_ns), groundTruthCdr(stamp_ns, map_T_base));
}

void LiveView::pose(const MclEstimate& e, const Pose& map_T_odom, const ParticleSet* particles) {
  if (server_.subscribed(ch_pose_)) server_.publish(ch_pose_, uint64_t(e.stamp_ns), poseCdr(e));
  if (server_.subscribed(ch_tf_)) server_.publish(ch_tf_, uint64_t(e.stamp_ns), tfCdr(e.stamp_ns, map_T_odom, map_T_odom.inverse() * e.pose));
  const bool view = server_.subscribed(ch_topview_);
  if (particles && (view || server_.subscribed(ch_particles_)) && due(last_particles_ns_, e.stamp_ns)) {
    if (server_.subscribed(ch_particles_)) server_.publish(ch_particles_, uint64_t(e.stamp_ns), particlesCdr(e.stamp_ns, *particles, cfg_.particles));
    if (view) {
      const size_t n = particles->size(), step = particleStride(n, cfg_.particles);
      view_.particles.clear();
      for (size_t i = 0; i < n; i += step) {
        const Pose p = particles->pose(i);
        view_.particles.insert(view_.particles.end(), {float(p.x()), float(p.y()), float(p.yaw())});
      }
    }
  }
  if (!view) return;
  view_.have_pose = true, view_.pose = e;
  view_.status = fmt::format("{} | {} particles{}", toString(e.status), e.particles,
                             e.map_fit >= 0 ? fmt::format(" | map fit {:.0f}%", 100 * e.map_fit) : "");
  topView(e.stamp_ns);
}

void LiveView::vrs(const VirtualScan& v) {
  if (server_.subscribed(ch_vrs_)) server_.publish(ch_vrs_, uint64_t(v.stamp_ns), vrsCdr(v));
  if (!server_.subscribed(ch_topview_)) return;
  view_.vrs.clear();
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v.ranges[i])) continue;
    const double a = v.angleOf(i);
    const Eigen::Vector3d p = v.map_T_base * Eigen::Vector3d(v.ranges[i] * std::cos(a), v.ranges[i] * std::sin(a), 0);
    view_.vrs.insert(view_.vrs.end(), {float(p.x()), float(p.y())});
  }
  topView(v.stamp_ns);
}

void LiveView::tracks(const polyloc_tracks& t) {
  if (server_.subscribed(ch_tracks_)) server_.publish(ch_tracks_, uint64_t(t.stamp_ns), tracksCdr(t));
  if (server_.subscribed(ch_topview_)) view_.tracks.assign(t.tracks, t.tracks + std::min<uint32_t>(t.count, POLYLOC_MAX_TRACKS));
}

void LiveView::scan(size_t sensor, int64_t stamp_ns, std::span<const float> ranges) {
  if (sensor >= ch_scan_.size() || !ch_scan_[sensor] || !server_.subscribed(ch_scan_[sensor])) return;
  const Sensor& s = rig_.sensors[sensor];
  if (!std::holds_alternative<PlanarScannerSpec>(s.spec)) {
    if (due(last_depth_ns_[sensor], stamp_ns))
      server_.publish(ch_scan_[sensor], uint64_t(stamp_ns), rangesCloudCdr(stamp_ns, s.name, beams_[sensor], ranges));
    return;
  }
  const auto& spec = std::get<PlanarScannerSpec>(s.spec);
  const ScanShape shape{float(spec.angleMin()), float(spec.resolution_rad), float(spec.range_min), float(spec.range_max)};
  server_.publish(ch_scan_[sensor], uint64_t(stamp_ns), laserScanCdr(stamp_ns, s.name, shape, ranges));
}

void LiveView::depth(size_t sensor, int64_t stamp_ns, const DepthFilterResult& d) {
  if (sensor >= ch_depth_.size() || !ch_depth_[sensor] || !server_.subscribed(ch_depth_[sensor])) return;
  if (!due(last_depth_ns_[sensor], stamp_ns)) return;
  server_.publish(ch_depth_[sensor], uint64_t(stamp_ns), depthCdr(stamp_ns, d));
}

void LiveView::health(const polyloc_health& h) {
  if (server_.subscribed(ch_health_)) server_.publish(ch_health_, uint64_t(h.stamp_ns), healthJson(h, inputs_, server_.stats()));
}

void LiveView::topView(int64_t stamp_ns) {
  if (!due(last_view_ns_, stamp_ns)) return;
  view_.stamp_ns = stamp_ns;
  server_.publish(ch_topview_, uint64_t(stamp_ns), topViewJson(view_));
}

}  // namespace polyloc::live
