// The ground-truth virtual range scan of a simulated scene: per VRS segment, the nearest surface
// of the map (chairs as moved) or of a person between floor_clearance and robot_height, found
// with horizontal rays at the segment's centre every `height_step` from the floor clearance up.
// What a perfect VRS would hold; polyloc perceive compares its VRS with it (vrs_rmse_m).
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sim/people.hpp>
#include <polyloc/vrs/config.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace polyloc {

// Ranges in VrsConfig's segment layout (angle_min, resolution, range_max; +inf for nothing),
// from base_link at map_T_base (its heading; the rays are level). height_step must be > 0.
std::vector<float> trueVirtualScan(const RayCaster& map, const PeopleScene& people, const Pose& map_T_base,
                                   const VrsConfig& config, double height_step = 0.02);

// A VRS against the truth, over the segments where the truth has an obstacle within `reach`
// (what the VRS must show) and the VRS range does not come from a danger zone alone (virtual
// obstacles are in no truth): error = min(vrs, range_max) - truth.
struct VrsError {
  double rmse_m = 0, mean_abs_m = 0;
  size_t segments = 0;
  size_t missed = 0;  // VRS farther than the truth by more than 0.1 m (an obstacle not shown)
};
VrsError compareVirtualScan(std::span<const float> vrs, std::span<const uint8_t> source, std::span<const float> truth,
                            double range_max, double reach);

}  // namespace polyloc
