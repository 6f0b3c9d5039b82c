// CLEAR-MOT metrics of a multi-target tracker (Bernardin and Stiefelhagen, "Evaluating Multiple
// Object Tracking Performance: The CLEAR MOT Metrics", 2008), frame by frame:
//
// 1. a ground-truth object keeps last frame's hypothesis if that is still within match_distance;
// 2. the rest are matched by the Hungarian method on distance (pairs beyond match_distance are
//    not allowed); an object matched to another hypothesis than the one it last had is an
//    identity switch;
// 3. objects left over are misses, hypotheses left over are false positives.
//
// MOTA = 1 - (misses + false positives + id switches) / ground-truth objects; MOTP is the mean
// distance of the matches, RMSE its root mean square. Objects marked `care = false` (a person
// standing still, hidden or too far for the tracker) are "don't care", as in the KITTI and MOT
// benchmarks: a hypothesis on one is neither a match nor a false positive, and it is no miss.
// Track-seconds: the time hypotheses were matched to ground truth, summed over the matches.
// An object that comes back after more than forget_after_s out of view (don't-care or absent)
// is a new object for identities: a new hypothesis on it is a re-entry, counted apart, not an
// identity switch (a tracker is not asked to recognise people; infinity: plain CLEAR-MOT).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <map>
#include <span>
#include <vector>

namespace polyloc {

struct MotObject {
  uint64_t id = 0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  bool care = true;  // ground truth only
};

struct MotMetrics {
  size_t frames = 0;
  size_t ground_truth = 0;      // care objects, summed over frames
  size_t matches = 0;
  size_t misses = 0;
  size_t false_positives = 0;
  size_t id_switches = 0;
  size_t reentries = 0;         // new hypothesis on an object back after forget_after_s out of view
  double mota = 0;              // 1 - (misses + false_positives + id_switches) / ground_truth
  double motp_m = 0;            // mean distance of matches
  double rmse_m = 0;            // root mean square distance of matches
  double track_seconds = 0;     // matches times the frame interval
  double id_switches_per_100s = 0;
};

class MotAccumulator {
 public:
  explicit MotAccumulator(double match_distance = 0.5,
                          double forget_after_s = std::numeric_limits<double>::infinity())
      : threshold_(match_distance), forget_s_(forget_after_s) {}
  // One frame lasting dt_s: the ground truth and the tracker's hypotheses at one stamp. Objects
  // with a non-finite position are skipped.
  void addFrame(double dt_s, std::span<const MotObject> truth, std::span<const MotObject> hypotheses);
  MotMetrics metrics() const;

 private:
  double threshold_, forget_s_;
  double t_ = 0;                            // s, summed frame durations
  std::map<uint64_t, double> in_view_;      // truth id -> last time it was a care object
  std::map<uint64_t, uint64_t> current_;  // truth id -> hypothesis id matched in the last frame
  std::map<uint64_t, uint64_t> last_;     // truth id -> hypothesis id it was last matched to, ever
  MotMetrics m_;
  double sum_d_ = 0, sum_d2_ = 0;
};

}  // namespace polyloc
