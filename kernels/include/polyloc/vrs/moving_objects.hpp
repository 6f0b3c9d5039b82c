// The tracker's confirmed tracks as the VRS memory filter's moving objects (what polyloc
// perceive, and later polylocd, hand from tracking/ to vrs/).
#pragma once

#include <polyloc/tracking/tracker.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <vector>

namespace polyloc {

inline std::vector<MovingObject> movingObjects(const Tracks& tracks) {
  std::vector<MovingObject> out;
  for (const TrackState& t : tracks.items)
    if (t.status == TrackStatus::Confirmed) out.push_back({t.position, t.velocity, t.position_cov, tracks.stamp_ns});
  return out;
}

}  // namespace polyloc
