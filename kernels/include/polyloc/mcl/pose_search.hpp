// Exhaustive search of a small x, y, yaw window around a pose for the one whose beams fit the
// map best (correlative scan matching, as Olson's and Cartographer's real-time matcher do, here
// by ray casting): every candidate's beams are cast with windows around their measured ranges
// and scored by truncated squared range residuals, so people and clutter cost a constant and a
// wall a few centimetres off still pulls. Coarse to fine: the window at step_xy / step_yaw, then
// +- half a step around the best cell at a quarter step. Only level beams are scored
// (level_beams.hpp; all beams when a round has none): floor hits fit every candidate alike.
// Gauss-Newton refinement (refine.hpp) starts from the result: on maps whose walls are steps of
// grid cells its basin is a few centimetres only.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <span>

namespace polyloc {

struct PoseSearch {
  double window_xy = 0.1;                  // m: candidates within +- this in x and y ...
  double window_yaw = 0.0349065850398866;  // rad (2 deg): ... and yaw; 0 and 0: no search
  double step_xy = 0.05;                   // m: the coarse grid's step ...
  double step_yaw = 0.0174532925199433;    // rad (1 deg); the fine grid: +- half a step at a quarter
  double truncate = 0.1;                   // m: a residual costs at most this squared
  size_t beams_per_scan = 60;              // valid beams of each scan, evenly spread (0: all)
  // Per beam, cost of an offset from the given pose: pull x (dx^2 + dy^2 + dyaw^2) (m, rad), so
  // that where the scans do not decide (along a corridor) the nearest candidate wins. 0.05: an
  // offset of 10 cm costs what a residual of 2.2 cm does.
  double pull = 0.05;
  // The data's likelihood over the coarse grid, exp(-cost / (2 spread_sigma^2)) with the beams
  // counted as spread_beams (the pull left out), gives the result's spread, as Olson's
  // correlative matcher takes its covariance from the scores: the Hessian of one minimum says
  // nothing of a flat or many-minima landscape (along a corridor). 0: not computed.
  double spread_beams = 0;
  double spread_sigma = 0.03;  // m: a residual's std
};

struct PoseSearchResult {
  Pose pose;               // the best candidate (the given pose when nothing could be scored)
  double cost = 0;         // its sum of truncated squared residuals and pull (m^2)
  size_t beams = 0, inliers = 0;  // beams scored; of them within `truncate`
  size_t candidates = 0;
  // Second moment (x, y, yaw in map axes) of that likelihood about the best coarse candidate:
  // how far from the chosen pose the scans would put it (zero when not computed).
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
};

// scans as refinePose takes them. Candidates move the pose in the map's x, y and turn it about
// its own z axis (z, roll and pitch kept). Ties keep the first candidate: deterministic.
PoseSearchResult searchPose(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans,
                            const Pose& map_T_base, const PoseSearch& search);

}  // namespace polyloc
