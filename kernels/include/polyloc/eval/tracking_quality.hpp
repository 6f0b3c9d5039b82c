// People-tracking quality on a simulated run: the scenario is simulated in memory (its level
// planar scanners only), every scan goes through motion detection and tracking with the
// ground-truth pose (or the simulated wheel odometry), and the confirmed tracks are scored
// with CLEAR-MOT (mot_metrics.hpp) against the people of the scenario.
//
// Ground truth at a step: every person present. One counts ("care") when at least min_beams
// beams of the tracking scanners hit them within `range` (SimFrame::label, the beam's
// end attributed to the nearest person) and they walk at min_speed or faster; the rest are
// don't-care (hidden, too far, or standing still: a motion tracker does not see them, and
// drops their track after tracker.timeout). `strict` also counts people standing in view.
//
//   TrackingQuality q = evaluateTracking(scenario, map, scenario.config.tracking, {});
//   q.mot.mota, q.mot.rmse_m, q.mot.id_switches_per_100s
#pragma once

#include <polyloc/eval/mot_metrics.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/tracking/people_tracker.hpp>

#include <functional>
#include <vector>

namespace polyloc {

struct TrackingEvalOptions {
  bool odometry = false;        // poses from wheel odometry (tracks in odom; truth taken there through the robot)
  double match_distance = 0.5;  // m, CLEAR-MOT threshold
  size_t min_beams = 3;         // beams on a person for them to be visible ...
  double range = 8.0;           // m: ... within this range of the scanner
  double min_speed = 0.2;       // m/s: slower people are don't-care (except in `strict`)
  double forget_after = 2.0;    // s out of view after which a person's new track is a re-entry, not a switch
  double duration = 0;          // s simulated; 0: the scenario's
  bool keep_frames = false;     // fill TrackingQuality::frames (plots)
};

// One tracking step, in the map frame.
struct TrackingEvalFrame {
  double t = 0;                       // s since the start
  Pose map_T_base;                    // ground truth
  std::vector<MotObject> truth;       // per present person (id = person index)
  std::vector<TrackState> tracks;     // confirmed tracks
  std::vector<Detection> detections;  // of the step
};

struct TrackingQuality {
  MotMetrics mot;     // ground truth: visible, walking people
  MotMetrics strict;  // ground truth: visible people, standing ones too
  TrackingCounters counters;
  size_t people = 0;
  double sim_duration_s = 0;
  double wall_s = 0;      // simulation and tracking
  double tracking_s = 0;  // in PeopleTracker
  std::vector<TrackingEvalFrame> frames;
};

// Throws what the Simulator and PeopleTracker throw for scenarios or settings that cannot run.
TrackingQuality evaluateTracking(const Scenario& scenario, const Mesh& map, const TrackingConfig& config,
                                 const TrackingEvalOptions& options,
                                 const std::function<void(double)>& progress = {});

}  // namespace polyloc
