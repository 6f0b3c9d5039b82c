// Ground truth for evaluation: stamped map_T_base poses, sorted, looked up at any stamp by
// interpolating between the two neighbouring poses (Pose::interpolate: slerp + linear).
// Bad input is dropped and counted, never fatal: non-finite poses, repeated stamps.
#pragma once

#include <polyloc/io/tum.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace polyloc {

class GroundTruth {
 public:
  GroundTruth() = default;
  // max_gap_s: neighbours further apart than this are not interpolated between (a hole in the
  // ground truth says nothing about where the robot was), the stamp counts as not covered.
  explicit GroundTruth(std::vector<StampedPose> poses, double max_gap_s = 1.0);

  // The pose at `stamp_ns`; nullopt outside [first, last] or inside a gap.
  std::optional<Pose> at(int64_t stamp_ns) const;

  bool empty() const { return poses_.empty(); }
  size_t size() const { return poses_.size(); }
  int64_t firstNs() const { return poses_.empty() ? 0 : poses_.front().stamp_ns; }
  int64_t lastNs() const { return poses_.empty() ? 0 : poses_.back().stamp_ns; }
  const std::vector<StampedPose>& poses() const { return poses_; }
  uint64_t dropped() const { return dropped_; }  // non-finite or repeated stamps

 private:
  std::vector<StampedPose> poses_;
  int64_t max_gap_ns_ = 1000000000;
  uint64_t dropped_ = 0;
};


}  // namespace polyloc
