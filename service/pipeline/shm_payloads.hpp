// Kernel results as the payload structs of service/shm/include/polyloc_shm.h, and back (odometry).
#pragma once

#include <polyloc_shm.h>

#include <polyloc/mcl/localizer.hpp>
#include <polyloc/tracking/tracker.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <cstdint>
#include <vector>

namespace polyloc::pipeline {

polyloc_pose posePayload(const MclEstimate& e, const Pose& map_T_odom, int64_t latency_ns);
// Fills `out` (resized) with a polyloc_vrs and its ranges; returns the bytes.
uint32_t vrsPayload(const VirtualScan& v, bool enabled, std::vector<uint8_t>& out);
// Confirmed and tentative tracks, at most POLYLOC_MAX_TRACKS (confirmed first).
polyloc_tracks tracksPayload(int64_t stamp_ns, const Tracks& t);
Pose odometryPose(const polyloc_odometry& o);
polyloc_odometry odometryPayload(int64_t stamp_ns, const Pose& odom_T_base);
Pose posePose(const polyloc_pose& p);  // map_T_base of a pose payload
Pose mapOdomPose(const polyloc_pose& p);  // its map_T_odom correction
// Frames an input's health counts as rejected, for any reason.
inline uint64_t rejectedFrames(const polyloc_input_health& h) {
  return h.rejected_nan + h.rejected_size + h.rejected_stale + h.rejected_future;
}

}  // namespace polyloc::pipeline
