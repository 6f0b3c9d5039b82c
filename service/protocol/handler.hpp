// What the control server asks of the process behind it: polylocd implements ControlHandler
// over its pipeline, tests over a fake. The server turns each request into one call and the
// result into the reply (docs/protocol.md has the wire layouts of these structs).
//
// Threading: every call comes from the server's one thread, one call at a time, while the
// pipeline runs on its own threads. Implementations must be thread-safe with respect to the
// pipeline (take a snapshot under a lock, or read the newest published output) and should
// return quickly: a slow call delays every client of the server.
// A call that throws is answered with Status::Internal and logged; the server goes on.
#pragma once

#include "protocol/commands.hpp"

#include <polyloc/geometry/pose.hpp>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::protocol {

// Same values as POLYLOC_POSE_* in service/shm/include/polyloc_shm.h.
enum class PoseStatus : uint32_t { Initialising = 0, Tracking = 1, Uncertain = 2, Lost = 3 };

struct PoseReport {
  int64_t stamp_ns = 0;  // of the scan that ended the update
  Pose pose;             // map_T_base
  // Order x y z roll pitch yaw, as in the shm pose channel.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  PoseStatus status = PoseStatus::Initialising;  // Initialising: no pose yet (NotAvailable)
  double ess = 0;                                // effective sample size of the particle set
  uint32_t particles = 0;
};

// SETPOSE: seed the filter around `pose` (planar: z, roll, pitch 0). Unset spreads: the
// handler's defaults (polylocd: its MCL config's initial spread).
// The values as sent (not a Pose): a yaw of 1e30 must reach the checks, not be wrapped first.
struct PoseSeed {
  double x = 0, y = 0, yaw = 0;  // map frame, m and rad
  std::optional<double> sigma_xy_m;
  std::optional<double> sigma_yaw_rad;
  Pose pose() const { return Pose::planar(x, y, yaw); }
};

// One entry of the scanner list. Entry 0 is the VRS (in base_link: identity mount), then the
// raw scanners of the rig in configuration order.
struct ScannerInfo {
  std::string name;  // "vrs", "front", ...
  Pose mount;        // base_T_sensor
  uint32_t beams = 0;
};

// A scan as polar beams in its scanner's frame (the VRS: base_link). A beam without a return
// has range +infinity; angles in radians, counter-clockwise, 0 along the scanner's x axis.
struct PolarScan {
  int64_t stamp_ns = 0;
  std::vector<float> angles;
  std::vector<float> ranges;  // metres, same length as angles
};

struct Track {  // as polyloc_track in the shm interface
  uint32_t id = 0;
  bool confirmed = false;
  double x = 0, y = 0, vx = 0, vy = 0;  // map frame, m and m/s
  std::array<double, 4> covariance{};   // position, row-major 2x2
};

struct TrackList {
  int64_t stamp_ns = 0;
  std::vector<Track> tracks;
};

struct InputStatus {
  std::string name;    // channel: "scan/front", "odom", ...
  double rate_hz = 0;  // frames taken per second, recently
  uint64_t taken = 0;
  uint64_t rejected = 0;  // for any reason (NaN, size, stale, future)
  double silence_s = 0;   // since the last frame taken
  bool silent = false;    // silence over the input timeout
  double map_fit = -1;    // share of its beams the map explains at the estimate, smoothed; -1: not measured
};

struct HealthReport {
  int64_t stamp_ns = 0;  // CLOCK_REALTIME when made
  double uptime_s = 0;
  PoseStatus pose_status = PoseStatus::Initialising;
  uint64_t cycles = 0, poses = 0, vrs = 0, tracks = 0;  // pipeline cycles, outputs published
  double pose_rate_hz = 0;
  double cycle_p50_ms = 0, cycle_p99_ms = 0;
  std::vector<InputStatus> inputs;
  bool unfit = false;  // the scans do not fit the map (mcl.fit.min_explained): never tracking
};

class ControlHandler {
 public:
  virtual ~ControlHandler() = default;

  // The newest estimate; status Initialising (or nullopt) before the first one.
  virtual std::optional<PoseReport> pose() = 0;
  // Ok, BadArgument (e.g. outside the map) or NotAvailable (e.g. no map yet). The server has
  // checked that the values are finite and the spreads positive.
  virtual Status setPose(const PoseSeed& seed) = 0;
  // Restart from a uniform prior over the map's free space.
  virtual Status globalLocalization() = 0;

  virtual std::vector<ScannerInfo> scanners() = 0;  // [0] is the VRS
  // The newest scan of scanners()[index] (the server checks the index); nullopt: none yet.
  virtual std::optional<PolarScan> scan(uint32_t index) = 0;

  // VRS publication (the collision-avoidance input of the controller) on or off.
  virtual bool collisionAvoidance() = 0;
  virtual void setCollisionAvoidance(bool on) = 0;

  virtual TrackList tracks() = 0;
  virtual HealthReport health() = 0;
};

}  // namespace polyloc::protocol
