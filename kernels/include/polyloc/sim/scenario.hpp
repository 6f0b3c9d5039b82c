// A simulated run: which map, robot and rig (from a polyloc configuration file, optionally
// overridden), the route, the floor, people, chair moves, sensor noise and odometry drift, the
// duration and the seed. Read from YAML by loadScenario (scenario_yaml.cpp); docs/simulation.md
// lists every key with its default. Tests build one in code.
#pragma once

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/sim/chairs.hpp>
#include <polyloc/sim/floor.hpp>
#include <polyloc/sim/noise.hpp>
#include <polyloc/sim/people.hpp>
#include <polyloc/sim/trajectory.hpp>
#include <polyloc/sim/world.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

struct NoiseSettings {
  bool enabled = true;  // false: exact ranges, no artefacts, exact odometry
  GlassMode glass = GlassMode::Transparent;
  int max_bounces = 8;  // glass surfaces one beam may pass or be reflected by
  // Per rig sensor (same order); missing entries get defaultNoise() of the sensor's preset.
  std::vector<SensorNoise> sensors;
};

struct OdometrySettings {
  double rate_hz = 50.0;  // odometry, /tf odom->base_link and ground truth
  OdometryNoise noise;
};

// Closed-loop missions (polyloc eval nav, docs/navigation.md): where the controller's zones and
// goals are, and which goals to visit. The simulator itself does not use it.
struct NavigationSpec {
  std::string zones;               // the controller's zone file (rooms, doors, danger, goals); "" none
  std::vector<std::string> goals;  // goal names visited in order; empty: drawn at random (seed)
  double mission_timeout = 120;    // s of simulated time per mission
  double start_yaw = 0;            // rad: the robot's heading at the start (the route's first waypoint)
  // vrs.sources for the runs with the VRS on ({sensor, mode} as in docs/vrs.md); empty: the config's
  std::vector<std::pair<std::string, std::string>> vrs_sources;
};

struct Scenario {
  std::string file;        // where it was read from ("" when built in code)
  PolylocConfig config;    // map, robot, rig
  uint64_t seed = 1;
  int64_t start_time_ns = 1700000000LL * 1000000000LL;  // stamps start here (not 0: tf reads 0 as "latest")
  double duration = 0;     // s; 0 = the route's duration + 1 s
  RouteSpec route;
  FloorSpec floor;
  std::vector<PersonSpec> people;
  ChairMoves chairs;
  WorldSpec world;         // what the sensors see where it differs from the map
  NoiseSettings noise;
  OdometrySettings odometry;
  NavigationSpec navigation;
  std::string map_frame = "map", odom_frame = "odom", base_frame = "base_link";
};

// Throws ConfigError naming file, line and key (of the scenario or of the config it refers to).
// `base: other.yaml` starts from that scenario; each top-level section given here replaces the
// base's section as a whole.
Scenario loadScenario(const std::string& path);

// Noise for every sensor of the rig: defaults of its preset.
std::vector<SensorNoise> defaultSensorNoise(const Rig& rig);

}  // namespace polyloc
