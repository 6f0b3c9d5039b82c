// Repeated localisation trials on simulated drives, for the figures localisation must show:
// global localisation from a uniform prior at random starts, and kidnapping (the robot carried
// elsewhere mid-run without its odometry noticing). Each trial drives the scenario's robot
// (map, rig, noise, people) along a short random route through free space, feeds the Localizer
// in time order, and records the error after every round of sensor updates.
//
//   TrialOptions o;  o.trials = 50;  o.rounds = 20;
//   std::vector<TrialResult> r = runGlobalTrials(scenario, map, mcl_config, o);
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/sim/scenario.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace polyloc {

struct TrialOptions {
  size_t trials = 50;
  size_t rounds = 20;          // global: rounds allowed to converge; kidnap: rounds to recover
  size_t hold_rounds = 10;     // the error must then stay within tolerance this many more rounds
  size_t kidnap_after = 30;    // kidnap: rounds of tracking before the robot is carried away
  double pos_tol = 0.2;        // m, planar
  double yaw_tol = 0.0872664625997165;  // rad (5 deg)
  double route_length = 8.0;   // m: upper bound of each random drive
  uint64_t seed = 1;           // start poses and routes (the scenario's seed drives the noise)
};

struct TrialResult {
  size_t index = 0;
  Pose start;                      // true pose where the filter must find the robot
  std::vector<double> pos_err;     // m, per round after the start (kidnap: after the kidnapping)
  std::vector<double> yaw_err;     // rad, absolute
  int converged_round = -1;        // 1-based round from which the error stays within tolerance
  bool converged = false;          // converged_round <= rounds and held for hold_rounds
  double filter_s = 0;             // time spent in the Localizer
  uint64_t updates = 0;            // sensor updates weighed
  uint64_t injected = 0;           // particles injected by augmented MCL
};

using TrialProgress = std::function<void(size_t done, size_t total)>;

// Throws std::runtime_error when the map has no free floor for the robot.
std::vector<TrialResult> runGlobalTrials(const Scenario& base, const Mesh& map, const MclConfig& mcl,
                                         const TrialOptions& options, const TrialProgress& progress = {});
std::vector<TrialResult> runKidnapTrials(const Scenario& base, const Mesh& map, const MclConfig& mcl,
                                         const TrialOptions& options, const TrialProgress& progress = {});

// First round (1-based) from which every error stays within tolerance to the end, or -1.
int convergedRound(const std::vector<double>& pos_err, const std::vector<double>& yaw_err, double pos_tol,
                   double yaw_tol);

}  // namespace polyloc
