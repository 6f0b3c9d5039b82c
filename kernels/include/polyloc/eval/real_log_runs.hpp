// The runs of the real-log protocol (docs/localization.md "Real logs"), made from a RealLog: the
// even scans make the map, the odd scans are the test run, their logged (corrected) poses the
// ground truth. Two odometries drive the test run:
//
// - drift: the corrected path between consecutive test scans with seeded noise (OdometryDrift),
//   one odometry message at each scan's stamp; the main test, since most logs' ODOM lines are not
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

// Noise of the drift odometry per step between test scans (d metres travelled, a radians
// turned), drawn from counter-based random numbers of `seed`: translation error std
// translation * d (5% per metre), rotation error std rotation * |a| + rotation_per_m * d.
struct OdometryDrift {
  double translation = 0.05;
  double rotation = 0.05;
  double rotation_per_m = 0.02;  // rad per metre (1.1 deg/m)
  uint64_t seed = 1;
};

struct RealLogSplit {
  std::vector<size_t> map_scans, test_scans;  // indices into RealLog::scans
};
// Even scans (0, 2, 4, ...) map, odd scans test; `every` > 2 keeps every every-th of the test
// scans (long logs in tests), the map still gets every even scan.
RealLogSplit splitEvenOdd(const RealLog& log, size_t every = 2);

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

TestRun driftRun(const RealLog& log, const std::vector<size_t>& test, const OdometryDrift& drift,
                 double restamp_hz = 10.0);
TestRun ownOdometryRun(const RealLog& log, const std::vector<size_t>& test, double restamp_hz = 10.0);

// Odometry at stamp t: interpolated between the neighbouring messages, the first / last beyond
// the ends (sorted by stamp; as the localiser interpolates odometry to a scan's stamp).
Pose odometryAt(const std::vector<StampedPose>& odometry, int64_t t);

}  // namespace polyloc
