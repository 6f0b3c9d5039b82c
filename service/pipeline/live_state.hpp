// What polylocd last published, and the requests of the control endpoint, shared between the
// pipeline thread (writes outputs, takes requests) and the control server's thread (reads,
// posts requests). One mutex: both sides hold it for a copy only.
#pragma once

#include <polyloc_shm.h>

#include <polyloc/geometry/pose.hpp>

#include <Eigen/Core>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::pipeline {

struct LiveScan {  // a polar scan in its sensor's (or base_link's, for the VRS) frame
  int64_t stamp_ns = 0;
  float angle_min = 0, angle_increment = 0, range_min = 0, range_max = 0;
  std::vector<float> ranges;
};

struct PoseRequest {
  Pose pose;
  Eigen::Matrix<double, 6, 6> covariance;
};

class LiveState {
 public:
  struct Snapshot {
    std::optional<polyloc_pose> pose;
    std::optional<LiveScan> vrs;
    std::vector<std::optional<LiveScan>> scans;  // per rig sensor (planar scanners only)
    std::vector<polyloc_track> tracks;
    int64_t tracks_stamp_ns = 0;
    std::optional<polyloc_health> health;
    bool collision_avoidance = true;
  };
  explicit LiveState(size_t sensors) { s_.scans.resize(sensors); }

  Snapshot snapshot() const { std::lock_guard l(m_); return s_; }
  template <class F> void update(F&& f) { std::lock_guard l(m_); f(s_); }

  // Requests, taken by the pipeline thread at its next cycle.
  void requestPose(const PoseRequest& r) { std::lock_guard l(m_); pose_request_ = r, global_request_ = false; }
  void requestGlobal() { std::lock_guard l(m_); global_request_ = true, pose_request_.reset(); }
  void setCollisionAvoidance(bool on) { std::lock_guard l(m_); s_.collision_avoidance = on; }
  bool collisionAvoidance() const { std::lock_guard l(m_); return s_.collision_avoidance; }
  std::optional<PoseRequest> takePoseRequest() { std::lock_guard l(m_); auto r = pose_request_; pose_request_.reset(); return r; }
  bool takeGlobalRequest() { std::lock_guard l(m_); bool g = global_request_; global_request_ = false; return g; }

 private:
  mutable std::mutex m_;
  Snapshot s_;
  std::optional<PoseRequest> pose_request_;
  bool global_request_ = false;
};

}  // namespace polyloc::pipeline
