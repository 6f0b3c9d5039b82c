// People tracking settings, with defaults. The `tracking:` section of the polyloc config
// (maps/config/*.yaml) fills this struct; every field is a key there under the same name, in the
// nested mappings `motion:`, `cluster:` and `tracker:` (docs/tracking.md lists them).
#pragma once

#include <string>
#include <vector>

namespace polyloc {

// Motion detection (motion_detector.hpp): the endpoints of a scan are compared with the free
// space of earlier scans of the same scanner, ego-motion removed through the poses.
struct MotionConfig {
  double margin = 0.15;         // m: a point moved only if it lies this far inside earlier free space ...
  double margin_per_m = 0.01;   // ... plus this per metre of range (angular and pose error grow with it)
  double min_range = 0.1;       // m: closer returns are ignored (the robot's own body, dirt on the window)
  double max_range = 10.0;      // m: farther returns are not compared (beams too sparse for legs)
  // s: ages of the reference scans a scan is compared with. Young ones catch fast motion, old
  // ones the leg that stands on the floor during a step (it was free space a second ago).
  std::vector<double> reference_ages = {0.16, 0.4, 0.8, 1.2};
  double max_speed = 2.5;       // m/s: an object walking away moves at most this far behind where it was ...
  double recede_max = 0.6;      // m: ... and at most this far between a reference and now
  // Static memory: a cell (static_cell m square) hit on and off for static_time seconds, never
  // unseen for static_gap, holds something static (a shelf board that a low scan plane grazes
  // as the robot rolls); points there are not motion. People pass a cell in well under that.
  double static_time = 1.0;     // s
  double static_gap = 2.0;      // s
  double static_cell = 0.15;    // m
  // m: endpoints this close to a moved one join it when they are not static and were not there
  // in the oldest reference: the other leg of a person walking away, hidden from every reference.
  double grow_distance = 0.4;
  // The angular window grows by turn_margin rad per rad the scanner turned since the reference,
  // and by travel_margin rad per metre it moved: odometry's heading error grows with both. Poses
  // from localisation need little of it.
  double turn_margin = 0.03;
  double travel_margin = 0.0;
  int window_beams = 1;         // beams either side of the bearing that must also be free (at least)
  // The pose jumped (relocalisation), not the world: the references are forgotten and the scan
  // gives no motion when the pose moved more than jump_distance or turned more than jump_angle
  // since the previous scan, or when more than max_moved_fraction of the compared points moved.
  double jump_distance = 0.3;   // m
  double jump_angle = 0.349065850398866;  // rad (20 deg)
  double max_moved_fraction = 0.5;
};

// Clustering of moved points into detections (detections.hpp).
struct ClusterConfig {
  double distance = 0.6;        // m: points closer than this are one object (both legs, a stride apart)
  size_t min_points = 3;        // moved points (seeds) at least; fewer are noise (a thin table leg missed by a beam)
  double max_extent = 1.2;      // m: larger clusters are not one person and are dropped
  double surface_offset = 0.07; // m: a scanner sees the near faces of legs; centroid moved this far away from it
  double min_sigma = 0.03;      // m: floor of a detection's position standard deviation
};

// Multi-target tracking (tracker.hpp): a constant-velocity Kalman filter per track.
struct TrackerConfig {
  double acceleration_sigma = 2.5;  // m/s^2: white-noise acceleration of the motion model
  double measurement_sigma = 0.15;  // m: position noise of a detection (gait, partly seen legs)
  double gate = 3.5;                // Mahalanobis distance: detections farther away are not this track's
  int confirm_hits = 3;             // detections that confirm a tentative track ...
  double confirm_time = 1.0;        // s: ... within this time after it started, else it is dropped
  // m: a tentative track is confirmed only once it is this far from where it started. Thin or
  // grazing surfaces (table legs, the ramp) flicker in and out of a low scan plane, and a
  // flickering spot gives detections at one place; a walking person leaves it.
  double confirm_distance = 0.3;
  double timeout = 1.0;             // s without a detection: a track is dropped ...
  double empty_timeout = 0.2;       // s: ... sooner when the scanners see its place empty
  double empty_radius = 0.3;        // m: the place is the disc of this radius around the track
  double max_sigma = 0.6;           // m: a track whose position std grows past this is dropped
  double init_speed_sigma = 1.0;    // m/s: velocity std of a new track (velocity starts at 0)
  double max_speed = 2.5;           // m/s: faster estimates are clamped (no person runs indoors)
  double new_track_distance = 0.5;  // m: no new track this close to a confirmed one (its other leg)
  // A track confirmed near where a confirmed one was dropped up to revive_time ago (its position
  // moved on by its velocity, within revive_distance + revive_speed x the time gone) takes that
  // track's id: a person who was hidden behind another one keeps their identity (0: off).
  double revive_time = 10.0;        // s (crowd: 3 s revived 2 of 16 people back in view, 10 s 12)
  double revive_distance = 1.0;     // m
  double revive_speed = 1.0;        // m/s: growth of the search radius while gone
};

struct TrackingConfig {
  // Planar scanners used, by rig name; empty: every level planar scanner of the rig.
  std::vector<std::string> sensors;
  double sync_tolerance = 0.02;  // s: scans of several scanners this close in time are fused into one step
  MotionConfig motion;
  ClusterConfig cluster;
  TrackerConfig tracker;
};

}  // namespace polyloc
