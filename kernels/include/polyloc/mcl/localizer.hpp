// The localiser: one particle filter over a polygon map, fed with odometry and range frames of
// the sensors of one rig, giving a pose estimate with covariance and status. It owns no threads
// (TBB runs the particle weighting inside the caster's arena) and does no I/O.
//
//   Localizer loc(caster, mesh, config.rig, mcl_config);
//   loc.initGlobal(t0);  // or loc.initPose(pose, cov, t0)
//   for each message: loc.addOdometry(t, odom_T_base) / loc.addScan(sensor, t, ranges)
//   MclEstimate e = loc.estimate();
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/particles.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <span>
#include <vector>

namespace polyloc {

enum class MclStatus { Initialising, Tracking, Uncertain, Lost };
const char* toString(MclStatus s);

struct MclEstimate {
  int64_t stamp_ns = 0;
  Pose pose;                                             // map_T_base
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // x y z roll pitch yaw
  MclStatus status = MclStatus::Initialising;
  double ess = 0;           // effective sample size of the last weighting
  size_t particles = 0;
  uint64_t updates = 0;     // measurement updates so far
  bool refined = false;     // pose refined against the mesh (mcl.refine) in this round
  // Share of the round's beams that ended beyond the map's surface, where it has none, at the
  // estimate (fit_check.hpp: beams past obstacles that are gone are not counted)
  double seen_through = 0;
  bool contradicted = false;  // seen_through above mcl.fit.max_seen_through: the round doubts the estimate
  // Map fit: share of the beams the map explains at the estimate, smoothed over rounds (mcl.fit);
  // overall and per rig sensor (index as in the rig), -1 until measured. Below
  // mcl.fit.min_explained (`unfit`) the status is never tracking.
  double map_fit = -1;
  std::vector<double> sensor_fit;
  bool unfit = false;
  // The odometry noise scales the scans found (odometry_noise.hpp): translation, rotation.
  double odometry_scale_translation = 1, odometry_scale_rotation = 1;
  double range_bias = 0;    // m taken off the level scanners' ranges (mcl.range_bias)
  bool recovered = false;   // this round planted local recovery hypotheses (mcl.recovery)
  bool jumped = false;      // this round's pose moved more than mcl.max_jump beyond the odometry
  bool inconsistent = false;  // the refined pose failed the innovation gate (mcl.innovation_gate)
  // Global localisation in progress: the coarse round this estimate closed (1, 2, ...; at most
  // mcl.global_max_coarse_rounds); 0: not searching.
  uint32_t global_round = 0;
};

// Counted rejections and events, for logs and the health channel.
struct MclCounters {
  uint64_t odometry = 0, odometry_out_of_order = 0, odometry_gaps = 0;
  uint64_t odometry_invalid = 0;           // non-finite pose, or a coordinate beyond domain::kMaxCoordinate
  uint64_t poses_rejected = 0;             // initPose outside the map or its domain
  uint64_t particles_blocked = 0;          // weights zeroed: in solid or closer than the clearance
  uint64_t blocked_ignored = 0;            // blocked, but holding most of the weight: kept (blocked_max_mass)
  uint64_t weights_collapsed = 0;          // updates where every weight was zero (made uniform)
  uint64_t scans = 0, scans_rejected = 0;  // wrong size, all invalid, unknown sensor, stale
  uint64_t updates = 0, resamples = 0, injected = 0;
  uint64_t relocalizations = 0;  // global re-initialisations after a kidnapping (relocalize_rounds)
  uint64_t contradicted = 0;     // rounds whose beams saw through the map at the estimate (mcl.fit)
  uint64_t unfit = 0;            // rounds whose smoothed map fit was below mcl.fit.min_explained
  uint64_t refinements = 0, refinements_refused = 0;  // mcl.refine: accepted, refused
  uint64_t hypotheses = 0;  // refined modes planted back in global localisation (mcl.hypotheses)
  uint64_t recoveries = 0;  // rounds that planted local recovery hypotheses (mcl.recovery)
  uint64_t jumps = 0;       // published poses beyond mcl.max_jump of the previous one moved by odometry
  uint64_t inconsistent = 0;  // refined poses outside the innovation gate of the prediction
};

class Localizer {
 public:
  // `caster` is exact (Embree on `map`): the floor under particles and free space. `weigh`, when
  // given, is the representation the sensor models and the refinement cast against (mcl.caster,
  // mcl/weighing.hpp); it must outlive the Localizer. Throws std::invalid_argument for
  // mcl.sensors the rig lacks.
  Localizer(const RayCaster& caster, const Mesh& map, const Rig& rig, const MclConfig& config,
            const RayCaster* weigh = nullptr);
  ~Localizer();

  // Refuses (returns false, counts poses_rejected, changes nothing) a pose outside the map's box
  // plus domain::kMapMargin, or spreads outside their domain (geometry/domain.hpp); checkPose
  // gives the reason.
  bool initPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance, int64_t stamp_ns);
  std::optional<std::string> checkPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance) const;
  void initGlobal(int64_t stamp_ns);  // uniform over free floor space where the robot can stand

  // Cumulative odometry pose (odom_T_base), as nav_msgs/Odometry gives it. Older than the last
  // one: ignored and counted.
  void addOdometry(int64_t stamp_ns, const Pose& odom_T_base);
  // The odometry at a stamp, as a scan stamped then is predicted with (OdometryBuffer::at).
  Pose odometryAt(int64_t stamp_ns) const;
  // One frame of rig sensor `sensor` (index into the rig): ranges in the sensor's beam order
  // (BeamSet of its spec); NaN/inf/out of [range_min, range_max] are invalid beams. After enough
  // motion (update_min_distance / _angle) a round starts in which each sensor's next frame is
  // weighed; the round ends when every sensor has contributed (or the next round starts), and
  // only then the particles are resampled and the estimate renewed. Returns true when this call
  // ended a round: estimate() is new.
  bool addScan(size_t sensor, int64_t stamp_ns, std::span<const float> ranges);

  MclEstimate estimate() const;
  // A global search runs: from a uniform prior (initGlobal, relocalisation) until its last round.
  bool searching() const;
  const ParticleSet& particles() const;
  const MclCounters& counters() const;
  const MclConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
