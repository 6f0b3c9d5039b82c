// The simulator: drives the robot along the scenario's route, casts every sensor's beams against
// the map (chairs moved) and the people walking, applies noise and artefacts, integrates noisy
// odometry, and writes it all as ROS 2 messages through a RecordingWriter:
//
//   /tf_static                     base_link -> <sensor>, <camera> -> <camera>_optical (once)
//   /tf, /odom, /ground_truth      odom -> base_link, nav_msgs/Odometry, map pose (odometry rate)
//   /scan/<name>                   sensor_msgs/LaserScan per planar scanner (frame <name>)
//   /points/<name>                 sensor_msgs/PointCloud2 per lidar (x y z intensity ring)
//   /depth/<name>/image            32FC1 depth in metres, NaN invalid (frame <name>_optical)
//   /depth/<name>/amplitude        32FC1 amplitude (frame <name>_optical)
//   /depth/<name>/camera_info      sensor_msgs/CameraInfo
//   /depth/<name>/artefacts        mono8: ArtefactBits per pixel (truth for the depth filters)
//   /ground_truth/people           polyloc_msgs/TrackArray per level-scanner frame (status: beams on them)
//   /ground_truth/vrs              sensor_msgs/LaserScan, the true VRS (every 5th first-scanner frame)
//
// Work goes in chunks of one simulated second: all frames of a sensor in a chunk are cast in one
// batch (the caster spreads them over threads), people, glass and noise per frame with TBB.
// Random numbers are keyed by (seed, sensor, frame, beam), so the output does not depend on the
// thread count or the chunking: the same seed gives the same bytes.
#pragma once

#include <polyloc/io/recording.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sim/floor.hpp>
#include <polyloc/sim/people.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/sim/trajectory.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace polyloc {

namespace detail {
class SensorSim;  // kernels/sim/sensor_sim.hpp
struct SimCursor;
}

// One sensor frame as simulated, for tests and plots (not written to the recording).
struct SimFrame {
  size_t sensor = 0;
  uint64_t index = 0;      // frame number of this sensor
  int64_t stamp_ns = 0;
  double t = 0;            // s since the start
  Pose map_T_base, map_T_sensor;
  std::vector<float> exact;       // ideal range per beam (map, people, glass), +inf for a miss
  std::vector<float> measured;    // published range per beam: NaN invalid, +inf miss (ToF: range, not depth)
  std::vector<uint8_t> artefacts; // ArtefactBits per beam
  std::vector<uint32_t> label;    // label id (Simulator::map()) of the exact hit, 0 for a miss
};

struct SimHooks {
  std::function<void(const SimFrame&)> on_frame;  // every sensor frame, in time order
  std::function<void(int64_t stamp_ns, const Pose& map_T_base, const Pose& odom_T_base)> on_tick;
  std::function<void(double fraction_done)> on_progress;  // after each simulated second
};

struct SimSummary {
  double sim_duration_s = 0;
  uint64_t messages = 0;
  std::map<std::string, uint64_t> topics;  // messages per topic
  uint64_t floor_misses = 0;               // contact probes that found no floor
  size_t chairs_moved = 0;
  WorldChanges world;                      // where the world differs from the map (world.hpp)
};

class Simulator {
 public:
  // `map` as loaded (loadScenarioMap): the world is built from it (or from the scenario's own
  // world mesh) with chairs moved and the world's changes (world.hpp). Throws
  // std::invalid_argument or std::runtime_error for scenarios that cannot run (no waypoints, a
  // chair move or removal that finds nothing, clutter that finds no floor).
  Simulator(Scenario scenario, Mesh map);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  const Scenario& scenario() const { return scenario_; }
  // What the sensors see: the map with chairs moved and the world's changes, label "person" added.
  const Mesh& world() const { return world_; }
  const WorldChanges& worldChanges() const { return world_changes_; }
  uint32_t personLabel() const { return person_label_; }
  const RayCaster& caster() const;
  const Trajectory& trajectory() const { return *trajectory_; }
  const People& people() const { return *people_; }
  People& people() { return *people_; }  // the closed loop makes people wait for the robot
  const FloorModel& floor() const { return *floor_; }
  double duration() const { return duration_; }  // s
  Pose groundTruth(double t) const;              // map_T_base at t seconds
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& chairMoves() const { return chair_moves_; }

  SimSummary run(RecordingWriter& out, const SimHooks& hooks = {});

 private:
  friend class SimStepper;
  // Every odometry tick and sensor frame not simulated yet before c1 ns from the start, the robot
  // at state_at(t).
  void span(int64_t c1, const std::function<PlanarState(int64_t)>& state_at, detail::SimCursor& cur,
            RecordingWriter& out, const SimHooks& hooks, SimSummary& summary);

  Scenario scenario_;
  Mesh world_;
  WorldChanges world_changes_;
  uint32_t person_label_ = 0;
  std::unique_ptr<RayCaster> caster_;
  std::unique_ptr<Trajectory> trajectory_;
  std::unique_ptr<People> people_;
  std::unique_ptr<FloorModel> floor_;
  std::vector<std::unique_ptr<detail::SensorSim>> sensors_;
  std::vector<BeamSet> sensor_beams_;  // per rig sensor
  std::vector<int> level_scanners_;    // rig indices of the level planar scanners (people truth)
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> chair_moves_;
  double duration_ = 0;
};

// The simulator driven from outside (closed loop, sim/drive.hpp): the robot's planar state at each
// event comes from the caller instead of the scenario's route. Events (odometry ticks, sensor
// frames) come one time at a time, with the same messages, noise and random streams as run().
class SimStepper {
 public:
  explicit SimStepper(Simulator& sim);
  ~SimStepper();
  int64_t nextEventNs() const;  // from the start: the next odometry tick or sensor frame
  // Simulates everything due at nextEventNs() with the robot at `state` (the first call also
  // writes /tf_static).
  void emit(const PlanarState& state, RecordingWriter& out, const SimHooks& hooks = {});
  const SimSummary& summary() const { return summary_; }

 private:
  Simulator& sim_;
  std::unique_ptr<detail::SimCursor> cur_;
  SimSummary summary_;
};

// Loads the scenario's map file with its load options. Throws MapError.
Mesh loadScenarioMap(const Scenario& s);

}  // namespace polyloc
