// The runs of the real-log protocol (docs/localization.md "Real logs"), made from a RealLog: the
// even scans make the map, the odd scans are the test run, their logged (corrected) poses the
// ground truth. Two odometries drive the test run:
//
// - drift: the corrected path between consecutive scans with seeded noise (OdometryDrift), one
//   odometry message at each scan's stamp; the main test, since most logs' ODOM lines are not
//   plain wheel odometry (docs/benchmarks.md);
// - own: the log's ODOM lines, minus the copies of the corrected pose that corrected logs write
//   right after each scan (an ODOM line equal to the scan's logged pose), which are ground truth,
//   not odometry.
//
// Stamps: the recorded ones when the run's scans and odometry increase strictly; otherwise
// (zero, repeated, backwards) every message is restamped by its order in the log at
// `restamp_hz`, and TestRun::stamps says why.
#pragma once

#include <polyloc/eval/real_log.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/tum.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

// The drift odometry: what a robot's wheels would have reported, made from the corrected path.
// Between consecutive scans of the log (every scan, whatever the test run keeps, so that a
// decimated run sees the same odometry) the true step is taken as rotate-translate-rotate and
// each part gets Gaussian noise from counter-based random numbers of `seed`: the translation std
// `translation` x its length, each rotation std `rotation` x its angle + `rotation_per_m` x
// length / sqrt(2) (so the heading's std grows by rotation_per_m per metre). Slips: with
// probability length / slip_every_m a step also slides by slip_min_m..slip_max_m in a random
// direction and turns by slip_min_rad..slip_max_rad either way (a wheel over a threshold).
struct OdometryDrift {
  std::string name = "mid";
  double translation = 0.05;              // std per metre travelled (fraction)
  double rotation = 0.05;                 // rad std per rad turned
  double rotation_per_m = 0.0174532925199433;  // rad std per metre travelled (1 deg/m)
  double slip_every_m = 0;                // mean path between slips (0: none)
  double slip_min_m = 0.1, slip_max_m = 0.3;
  double slip_min_rad = 0.0872664625997165, slip_max_rad = 0.174532925199433;  // 5..10 deg
  uint64_t seed = 1;
};

// The named levels: "low" (2 %, 0.5 deg/m), "mid" (5 %, 1 deg/m), "high" (10 %, 2 deg/m),
// "slip" (mid, and a slip every 10 m on average), or "P/D" (P % and D deg/m; the rotation per
// rad turned P %), "+slip" after any of them adding slips. Throws std::invalid_argument naming
// the spec otherwise.
OdometryDrift parseDrift(const std::string& spec);
// "mid: 5 %/1 deg per m" etc.
std::string describeDrift(const OdometryDrift& drift);

struct RealLogSplit {
  std::vector<size_t> map_scans, test_scans;  // indices into RealLog::scans
};
// Even scans (0, 2, 4, ...) map, odd scans test; `every` > 2 keeps every every-th of the test
// scans (long logs in tests), the map still gets every even scan.
RealLogSplit splitEvenOdd(const RealLog& log, size_t every = 2);
// The first `count` scans of a split's test scans, every `decimate`-th of them.
std::vector<size_t> decimateScans(const std::vector<size_t>& scans, size_t decimate, size_t count = SIZE_MAX);

struct TestRun {
  std::string name;                        // "drift", "own"
  std::vector<RecordedMessage> messages;   // /odom and the scans on the log's topic, time order
  std::vector<StampedPose> truth;          // each test scan's logged pose, at its (run) stamp
  std::vector<StampedPose> odometry_only;  // odometry alone, chained from the first truth pose
  std::string stamps = "recorded";         // or "restamped by order at N Hz: why"
  uint64_t odometry = 0;                   // odometry messages in the run
  uint64_t odometry_dropped = 0;           // own: ODOM lines that copy a scan's logged pose
  // Why the run cannot be localised as the protocol means it ("" when it can): own, a log whose
  // ODOM lines are only copies of the logged poses has no odometry of its own.
  std::string unusable;
};

// The drift odometry at every scan of the log (odom_T_base, starting at the identity).
std::vector<Pose> driftOdometry(const RealLog& log, const OdometryDrift& drift);
// The test scans with the drift odometry of every log scan from the first test scan to the last
// (one odometry message per scan of the log, as a robot's odometry comes faster than a test
// run's scans), the logged poses as /ground_truth.
TestRun driftRun(const RealLog& log, const std::vector<size_t>& test, const OdometryDrift& drift,
                 double restamp_hz = 10.0);
TestRun ownOdometryRun(const RealLog& log, const std::vector<size_t>& test, double restamp_hz = 10.0);

// Odometry at stamp t: interpolated between the neighbouring messages, the first / last beyond
// the ends (sorted by stamp; as the localiser interpolates odometry to a scan's stamp).
Pose odometryAt(const std::vector<StampedPose>& odometry, int64_t t);

}  // namespace polyloc
