// Multi-target tracking of moving people: one constant-velocity Kalman filter per track,
// detections gated by Mahalanobis distance and assigned to tracks with the Hungarian method.
// A track starts tentative at an unassigned detection, is confirmed after confirm_hits
// detections within confirm_time once it moved confirm_distance from its start, and is dropped after `timeout` without a detection or when
// its position uncertainty grows past max_sigma; sooner once the sensors see its place empty
// (the person is gone, or turned away from the prediction).
//
//   MultiTargetTracker tracker(config.tracker);
//   tracker.update(stamp_ns, detections);
//   const Tracks& t = tracker.tracks();   // t.inside(point, 2.0): in a confirmed track's 2-sigma ellipse
#pragma once

#include <polyloc/tracking/config.hpp>
#include <polyloc/tracking/detections.hpp>
#include <polyloc/tracking/kalman.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace polyloc {

enum class TrackStatus : uint8_t { Tentative, Confirmed, Deleted };
// What the sensors saw at a track's predicted place (PeopleTracker asks its motion detectors).
enum class Visibility : uint8_t { Unknown, Hidden, Empty, Occupied };
using VisibilityFn = std::function<Visibility(const Eigen::Vector2d&)>;
const char* trackStatusName(TrackStatus s);

struct TrackState {
  uint32_t id = 0;                  // unique for the tracker's lifetime, from 1
  TrackStatus status = TrackStatus::Tentative;
  Eigen::Vector2d position = Eigen::Vector2d::Zero(), velocity = Eigen::Vector2d::Zero();
  Eigen::Matrix2d position_cov = Eigen::Matrix2d::Identity(), velocity_cov = Eigen::Matrix2d::Identity();
  Ellipse ellipse;                  // of position_cov at 1 sigma
  int64_t first_ns = 0, last_detection_ns = 0;
  uint32_t hits = 0;                // detections assigned
};

// The tracks at one stamp: the live ones and those the last update dropped (status Deleted).
struct Tracks {
  int64_t stamp_ns = 0;
  std::vector<TrackState> items;

  // Whether p lies in the ellipse of a confirmed track at `sigmas` standard deviations, grown by
  // `radius` (m, a person's body around the tracked point): the obstacle memory keeps such points
  // out. The growth adds radius^2 / sigmas^2 to the covariance, so every axis is at least `radius`.
  bool inside(const Eigen::Vector2d& p, double sigmas, double radius = 0.0) const;
  size_t confirmed() const;
};

class MultiTargetTracker {
 public:
  explicit MultiTargetTracker(const TrackerConfig& config = {});

  // Predicts every track to stamp_ns, assigns the detections, updates, starts, confirms and drops
  // tracks. `seen` tells what the sensors saw at a predicted place: a track without a detection
  // whose place has been Empty for empty_timeout is dropped. A stamp before the last update is ignored (returns false); non-finite detections
  // are skipped.
  bool update(int64_t stamp_ns, std::span<const Detection> detections, const VisibilityFn& seen = {});
  const Tracks& tracks() const { return snapshot_; }
  // The live tracks predicted to a later stamp (nothing is changed).
  Tracks predicted(int64_t stamp_ns) const;
  void clear();

 private:
  struct Track {
    uint32_t id = 0;
    TrackStatus status = TrackStatus::Tentative;
    ConstantVelocityKalman kf;
    int64_t first_ns = 0, last_detection_ns = 0;
    uint32_t hits = 0;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // first detection
    int64_t not_empty_ns = 0;  // last detection, or last time its place was not seen empty
  };
  static TrackState stateOf(const Track& t);
  void snapshot(int64_t stamp_ns, const std::vector<Track>& dropped);

  TrackerConfig c_;
  void revive(Track& t, int64_t stamp_ns);
  std::vector<Track> tracks_;
  struct Lost {
    uint32_t id;
    Eigen::Vector2d position, velocity;
    int64_t stamp_ns;
  };
  std::vector<Lost> lost_;  // confirmed tracks dropped lately (revive_time), for their ids
  uint32_t next_id_ = 1;
  int64_t stamp_ns_ = 0;
  bool started_ = false;
  Tracks snapshot_;
};

}  // namespace polyloc
