// polylocd's live view (docs/live.md): a FoxgloveServer with polylocd's channels, fed by the
// daemon's pipeline thread. Every call returns at once when nobody subscribed to what it feeds;
// otherwise it encodes (particles, depth and the top view at most `rate` times a second of data
// time) and hands the bytes to the server, which never makes the caller wait for a client.
//
//   LiveView live(cfg.live, map, rig, input_names);   // binds; throws naming address:port
//   live.pose(estimate, map_T_odom, particles);        // from PipelineSink::onPose, and so on
#pragma once

#include "live/foxglove_server.hpp"
#include "live/live_messages.hpp"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace polyloc::live {

// The `polylocd.live` section (docs/polylocd.md).
struct LiveConfig {
  std::string address = "127.0.0.1";  // loopback by default; 0.0.0.0 opens it to the network
  uint16_t port = 8765;               // 0: no live view
  int max_clients = 8;
  double max_queue_mib = 8;           // per client
  double stall_timeout_s = 3;         // over the queue limit this long: disconnected
  int max_pending = 16;               // connections in their handshake; more are closed at once
  double handshake_timeout_s = 3;     // s: a connection that has not finished its handshake is closed
  int max_subscriptions = 64;         // per client
  double max_client_rate = 50;        // client messages per second (bursts of as many); more are refused
  size_t particles = 500;             // at most this many particles per message
  double rate_hz = 10;                // particles, depth clouds and the top view, per second of data time
  float slice_height = 0.3f;          // m: the map slice the page draws
  bool ground_truth = false;          // a /ground_truth channel (polyloc play --live: the source's truth)
};

class LiveView {
 public:
  LiveView(const LiveConfig& cfg, const Mesh& map, const Rig& rig, std::vector<std::string> inputs);
  ~LiveView();

  // particles null: none to show (polyloc play --live sees only the published pose).
  void pose(const MclEstimate& e, const Pose& map_T_odom, const ParticleSet* particles);
  void groundTruth(int64_t stamp_ns, const Pose& map_T_base);  // needs LiveConfig::ground_truth
  void vrs(const VirtualScan& v);
  void tracks(const polyloc_tracks& t);
  // A range sensor's frame: planar scanners as LaserScan, lidars as a cloud (at most `rate`).
  void scan(size_t sensor, int64_t stamp_ns, std::span<const float> ranges);
  void depth(size_t sensor, int64_t stamp_ns, const DepthFilterResult& d);
  void health(const polyloc_health& h);

  uint16_t port() const { return server_.port(); }
  ServerStats stats() const { return server_.stats(); }

 private:
  bool due(int64_t& last_ns, int64_t stamp_ns) const;
  void topView(int64_t stamp_ns);

  LiveConfig cfg_;
  const Rig& rig_;
  std::vector<std::string> inputs_;
  FoxgloveServer server_;
  uint32_t ch_map_ = 0, ch_slice_ = 0, ch_pose_ = 0, ch_particles_ = 0, ch_tf_ = 0, ch_tf_static_ = 0, ch_vrs_ = 0,
           ch_tracks_ = 0, ch_health_ = 0, ch_topview_ = 0, ch_truth_ = 0;
  std::vector<uint32_t> ch_scan_, ch_depth_;  // per rig sensor, 0: none
  TopView view_;                              // what the next top view shows
  int64_t last_particles_ns_ = INT64_MIN, last_view_ns_ = INT64_MIN;
  std::vector<int64_t> last_depth_ns_;  // per sensor: depth cameras and lidars (rate)
  std::vector<BeamSet> beams_;           // per sensor: lidars' beam directions
};

}  // namespace polyloc::live
