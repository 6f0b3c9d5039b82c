// Nearness Diagram (ND) navigation, after Minguez & Montano, "Nearness Diagram (ND) Navigation:
// Collision Avoidance in Troublesome Scenarios" (IEEE T-RA 20(1), 2004): the reactive method of
// the thesis polyloc follows. It divides the scene instead of weighing forces, so it drives
// through narrow doors and dense clutter where potential fields oscillate or stall.
//
// From one polar scan and the goal (both in base_link), with distances measured from the
// rectangular hull (RectHull::clearance) instead of a circular robot's centre:
//  1. discontinuities: adjacent beams whose clearances differ by more than the hull's width
//     (the robot could fit into the step); nothing seen counts as range_max;
//  2. regions between discontinuities; a valley is a region with at least one rising
//     discontinuity (an obstacle edge beside it, nearer than the region), or the whole scan when
//     there is no discontinuity at all;
//  3. the free walking area: when the straight path to the goal is clear for the hull's width,
//     the goal's direction; else the navigable valley closest to the goal (0 when the goal's
//     direction lies in it, else the angle to its nearest navigable rising discontinuity). A
//     rising discontinuity is navigable when the gap from its edge point to the nearest obstacle
//     point across the valley (within half a turn) is at least the hull's width;
//  4. the situation and its direction of motion (theta_t: the high-safety direction):
//       HSGR  goal in the region:                    theta_t = the goal's direction
//       HSWR  wide valley (> wide_valley_deg):       theta_t = rising edge + wide_valley_deg / 2, into the valley
//       HSNR  narrow valley:                         theta_t = the valley's middle
//       LS1   obstacles within safety_distance of the hull on one side of theta_t: turned away from
//             the closest one, the more the nearer: its angle from the obstacle grows from
//             alpha (= |theta_t - theta_obs|) at safety_distance to pi at contact
//       LS2   on both sides: the bisector of the closest obstacle on each side, turned towards the
//             farther one by (pi / 4) x (d_left - d_right) / safety_distance (centring)
//       Blocked  no navigable valley and no straight path: v = w = 0.
//  5. speed: steer() (local_command.hpp) with the scale 1 in high safety and
//     d_obs / safety_distance in low safety (d_obs: the smallest clearance).
#pragma once

#include <polynav/hull.hpp>
#include <polynav/local_command.hpp>
#include <polynav/polar_scan.hpp>

#include <Eigen/Core>

namespace polynav {

struct NdConfig {
  double safety_distance = 0.3;  // m, the security zone around the hull; > 0
  double wide_valley_deg = 90;   // smax: a valley wider than this is wide; in (0, 360]
};

enum class NdSituation { HSGR, HSWR, HSNR, LS1, LS2, Blocked };
const char* situationName(NdSituation s);  // "HSGR", ..., "Blocked"

struct NdCommand : LocalCommand {
  NdSituation situation = NdSituation::Blocked;
};

// One ND step (see above). A goal at the origin gives v = w = 0 (HSGR). Throws
// std::invalid_argument naming the field for a goal that is not finite, a bad scan
// (PolarScan::validate), a bad hull (RectHull::validate), config or limits.
NdCommand nearnessDiagram(const PolarScan& scan, const Eigen::Vector2d& goal_in_base, const RectHull& hull,
                          const NdConfig& config = {}, const NdLimits& limits = {});

}  // namespace polynav
