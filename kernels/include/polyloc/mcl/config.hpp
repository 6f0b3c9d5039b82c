// Monte-Carlo localisation settings, with defaults. The `mcl:` section of the polyloc config
// (maps/config/*.yaml) fills this struct; every field below is a key there (docs/localization.md).
#pragma once

#include <cstdint>
#include <string>

namespace polyloc {

struct MotionNoise {
  // Odometry noise (Thrun's alpha1..alpha4): rotation from rotation, rotation from translation,
  // translation from translation, translation from rotation.
  double alpha1 = 0.05, alpha2 = 0.02, alpha3 = 0.05, alpha4 = 0.02;
  // 6-DoF diffusion per metre travelled (dof: 6): z (m), roll and pitch (rad).
  double z_per_m = 0.01, roll_pitch_per_m = 0.005;
  bool omni = false;  // omni drive: x, y, yaw noise independent; else differential (rot-trans-rot)
};

struct BeamModel {
  double sigma_hit = 0.05;     // m, measurement noise of a hit (plus map error)
  double z_hit = 0.85, z_short = 0.05, z_max = 0.05, z_rand = 0.05;
  double lambda_short = 1.0;   // 1/m
  double window_sigmas = 4.0;  // rays only look at measured range +- this many sigma_hit ...
  double window_min = 0.3;     // ... but at least +- this (m), so a short hit is still seen
  // Multiplies a scan's summed log-likelihood. Beams are not independent (map error, people):
  // < 1 tempers the product so that a spread cloud (global init, symmetric places) keeps its
  // modes instead of collapsing onto the luckiest particle.
  double log_scale = 1.0;
};

struct MclConfig {
  int dof = 3;                      // 3: x, y, yaw on the floor; 6: full pose
  std::string model = "beam";       // scanners, lidar: beam | likelihood_field | plane_fragments
  std::string depth_model = "beam"; // depth cameras: beam | likelihood_field | depth | none
  size_t particles = 2000;          // initial count (tracking)
  size_t min_particles = 500;       // KLD-sampling bounds
  size_t max_particles = 20000;
  size_t global_particles = 20000;  // for global localisation
  bool kld = true;
  double kld_epsilon = 0.05, kld_z = 2.33;  // 99% quantile
  double kld_bin_xy = 0.2, kld_bin_yaw = 0.175;  // m, rad (10 deg)
  double resample_ess = 0.5;        // resample when ESS / N drops below this
  double alpha_slow = 0.001, alpha_fast = 0.1;  // augmented MCL (0 disables injection)
  size_t beams_per_scan = 60;       // per sensor per update
  std::string subsample = "uniform";  // uniform | random
  double update_min_distance = 0.05;  // m travelled before the next update ...
  double update_min_angle = 0.05;     // ... or rad turned
  double robot_radius = 0.25;       // particles closer than this to a surface get zero weight
  double body_height = 0.4;         // m above base_link where the clearance above is checked
  double uncertain_xy = 0.3;        // m: position std above this (or a weak dominant cluster)
  double uncertain_yaw = 0.2;       // rad   ... gives status Uncertain
  MotionNoise motion;
  BeamModel beam;
  uint64_t seed = 1;
  int threads = 0;                  // 0 = all cores
};

}  // namespace polyloc
