// Ground truth beyond the pose, written by the Simulator next to the sensor topics so that
// polyloc perceive can score a recording: the people (/ground_truth/people), the true virtual
// range scan (/ground_truth/vrs) and the ToF artefact tags (/depth/<camera>/artefacts).
#pragma once

#include "sensor_sim.hpp"

#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sim/people.hpp>
#include <polyloc/sim/scenario.hpp>

#include <vector>

namespace polyloc::detail {

// The people present at a frame of a level planar scanner, status = how many of the frame's
// beams end on them (at most 255), velocity and a nominal 5 cm covariance; map frame.
OutMessage peopleTruth(const SimFrame& frame, const BeamSet& beams, const People& people, const PeopleScene& scene,
                       uint32_t person_label, const std::string& map_frame, int order);
// The true VRS (sim/vrs_truth.hpp) at the frame's robot pose, as a LaserScan in base_link.
OutMessage vrsTruth(const SimFrame& frame, const RayCaster& map, const PeopleScene& scene, const VrsConfig& config,
                    const std::string& base_frame, int order);
// A depth camera frame's ArtefactBits per pixel as a mono8 image (row-major, like the depth image).
OutMessage artefactImage(const SimFrame& frame, const Sensor& camera, int order);

}  // namespace polyloc::detail
