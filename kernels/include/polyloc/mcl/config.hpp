// Monte-Carlo localisation settings, with defaults. The `mcl:` section of the polyloc config
// (maps/config/*.yaml) fills this struct; every field below is a key there (docs/localization.md).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace polyloc {

// Odometry noise adapted to the evidence (odometry_noise.hpp): the alphas are scaled by how far
// the scan-matched motion (refined estimates of consecutive rounds) departs from the odometry.
struct OdometryNoiseAdapt {
  bool enabled = true;
  double gain = 0.2;           // weight of one innovation in the smoothed log variance ratio
  double max_log_ratio = 2.0;  // one innovation moves the variance by at most e^(gain * this)
  double min_scale = 1.0;      // the alphas are the least noise assumed ...
  double max_scale = 8.0;      // ... and at most this many times them
  double min_step = 0.1;       // m: shorter steps (that also turn less than min_turn) say little
  double min_turn = 0.1;       // rad
};

struct MotionNoise {
  // Odometry noise (Thrun's alpha1..alpha4): rotation from rotation, rotation from translation,
  // translation from translation, translation from rotation.
  double alpha1 = 0.05, alpha2 = 0.02, alpha3 = 0.05, alpha4 = 0.02;
  // 6-DoF diffusion per metre travelled (dof: 6): z (m), roll and pitch (rad).
  double z_per_m = 0.01, roll_pitch_per_m = 0.005;
  bool omni = false;  // omni drive: x, y, yaw noise independent; else differential (rot-trans-rot)
  // Heavy tails: this share of the particles moves with outlier_scale times the noise, for
  // odometry that slips and jumps (a wheel over a threshold, a log whose odometry is off by
  // 20 deg now and then). Off by default: in corridors such particles, far along the corridor,
  // win now and then (aces: a 0.8 m frame at 0.1).
  double outlier_ratio = 0;
  double outlier_scale = 5.0;
  // The alphas are multiplied by this for the prediction after a round the fit check
  // contradicted (mcl.fit): a slip the Gaussian noise cannot follow is caught a round later.
  double recovery_scale = 4.0;
  OdometryNoiseAdapt adapt;
};

struct BeamModel {
  double sigma_hit = 0.1;      // m, measurement noise of a hit plus map error (real maps: cm off, walls of cells)
  double z_hit = 0.85, z_short = 0.05, z_max = 0.05, z_rand = 0.05;
  double lambda_short = 1.0;   // 1/m
  double window_sigmas = 4.0;  // rays only look at measured range +- this many sigma_hit ...
  double window_min = 0.2;     // ... but at least +- this (m), so a short hit is still seen
  // Multiplies a scan's summed log-likelihood. Beams are not independent (map error, people):
  // < 1 tempers the product so that a spread cloud (global init, symmetric places) keeps its
  // modes instead of collapsing onto the luckiest particle.
  double log_scale = 1.0;
  // While the filter is not tracking (SensorFrame::coarse): wider and tempered, so that the few
  // particles of a uniform prior near the truth are not outweighed by a lucky fit elsewhere.
  double coarse_sigma_hit = 0.2;
  double coarse_log_scale = 0.1;
};

// Likelihood-field model (likelihood_field.hpp): each beam endpoint scored by its distance to
// the nearest map surface, looked up in a 3D distance field built once from the mesh.
struct LikelihoodField {
  double sigma_hit = 0.05;     // m: endpoint-to-surface noise (sensor plus map error)
  double z_hit = 0.9;          // weight of the Gaussian on the distance
  double z_rand = 0.1;         // weight of the uniform random return (density z_rand / range_max)
  double resolution = 0.05;    // m: distance field grid; keep <= sigma_hit (interpolation error ~h/2)
  double max_distance = 1.0;   // m: distances clamp here (far beyond sigma_hit the Gaussian is 0)
  double log_scale = 1.0;      // tempering, as beam.log_scale
};

// Plane-fragment model (plane_fragments.hpp): lines fitted per 2D scan, lines of two scan
// planes that cross combined into surface patches (point + normal), compared with the map.
struct PlaneFragments {
  double split_threshold = 0.03;  // m: split a segment where a point lies farther off its chord
  size_t min_points = 8;          // points of a segment; fewer: noise, not a surface
  double min_length = 0.2;        // m: shorter segments give poorly defined directions
  double max_gap = 0.2;           // m between consecutive points: farther apart, a new segment
  double intersect_tolerance = 0.05;  // m: two segment lines closer than this meet
  double extent_margin = 0.1;     // m: ... where the meeting point may lie beyond a segment's end
  double min_angle = 0.349065850398866;  // rad (20 deg): flatter crossings give unstable normals
  double sigma_distance = 0.05;   // m: fragment point vs map along the ray
  double sigma_angle = 0.174532925199433;  // rad (10 deg): fragment normal vs map normal
  double z_hit = 0.9;             // weight of the fragment-explained-by-the-map term
  double z_rand = 0.1;            // constant floor: clutter, people, map errors
  double window = 0.3;            // m: rays only look at expected distance +- this
  double max_age = 0.5;           // s: older segments of the other scanners are not combined
  size_t max_fragments = 100;     // per frame, spread evenly over the found ones (0: all)
  double log_scale = 1.0;         // tempering, as beam.log_scale
};

// Local refinement of the estimate (refine.hpp): point-to-plane Gauss-Newton against the mesh.
struct RefineConfig {
  bool enabled = true;               // the Localizer runs refinePose after each update
  int iterations = 10;               // Gauss-Newton iterations at most (each re-casts)
  size_t beams_per_scan = 180;       // valid beams per scan, spread evenly (0: all)
  double max_correspondence = 0.15;  // m: larger |residual| is an outlier, dropped
  double huber = 0.03;               // m: Huber threshold of the robust weight
  double min_step = 1e-5;            // m / rad: converged when the step is below this
  double max_final_step = 1e-3;      // m / rad: a larger last step when iterations run out: circling, the least-cost iterate is taken
  size_t min_correspondences = 20;   // fewer: refused
  double max_correction = 0.3;       // m: larger corrections are refused (a wrong-mode estimate)
  double max_correction_yaw = 0.1;   // rad: bound on the rotation angle of the correction
  // Of the selected beams, at least this fraction must be inliers at the end, else refused. The
  // gate above keeps far-off starts from travelling far: from 0.2-1 m off they settle where only
  // some walls agree (40-60% inliers, versus ~100% at the true pose in a mapped room). Real scans
  // see people and what the map lacks: at 0.7, a quarter of the CARMEN test scans were refused
  // at the right place; the fit check (mcl.fit) catches wrong places.
  double min_inlier_ratio = 0.5;
  double cast_margin = 1.0;          // m: rays stop at measured range + this (early traversal exit)
  // Before Gauss-Newton, an exhaustive search of x, y +- search_xy and yaw +- search_yaw
  // (pose_search.hpp) with search_beams beams per scan: on real maps (walls of grid cells,
  // centimetres off) the refinement's basin is a few centimetres and the cloud's mean is not
  // always in it. 0 and 0: none.
  double search_xy = 0.1;
  double search_yaw = 0.0349065850398866;  // rad (2 deg)
  double search_step_xy = 0.05;            // m: the coarse grid (then a quarter step around its best)
  double search_step_yaw = 0.0174532925199433;  // rad (1 deg)
  size_t search_beams = 120;
  // The localiser widens the search to search_sigmas of the prediction's std (the last estimate's
  // and the odometry's since), up to max_search_xy / max_search_yaw: long steps on bad odometry
  // leave the cloud decimetres off (real logs, every 4th scan: 6 m between updates).
  double search_sigmas = 2.0;
  double max_search_xy = 0.5;              // m
  double max_search_yaw = 0.139626340159546;  // rad (8 deg)
  // The localiser adds the spread of the search's likelihood (pose_search.hpp: the data over the
  // coarse grid, beams counted as mcl.effective_beams, residual std huber) to the fit's
  // covariance: along a corridor the Hessian of the minimum Gauss-Newton found said 4-9 cm while
  // the estimate drifted 0.58 m off (real logs, infinite-corridor). false: the Hessian's alone.
  bool search_spread = true;
  // Degrees of freedom refined: 0 = the filter's dof; 6 also with dof 3, so that the tilted
  // scanners' view of the floor corrects z, roll and pitch taken from the floor under the robot.
  int dof = 0;
  // Raw ToF frames carry flying pixels and multipath returns that pass the residual gate and
  // bias the fit (about 0.2 deg of yaw on lab_tour); filtered depth could.
  bool depth_cameras = false;
  // Range bias (map proudness): the level scanners' ranges run this much longer than the map
  // says (m), estimated with the pose (a seventh parameter, prior std range_bias_prior around
  // the bias already applied) and followed by the localiser (mcl.range_bias). An occupancy grid
  // extruded cell by cell puts each wall face up to a cell in front of the surface the scans saw
  // (real logs, end-point maps: about half a cell); a scan then fits the map only shifted back.
  bool range_bias = false;
  double range_bias_prior = 0.05;
};

// Depth-camera model (depth_model.hpp): the beam mixture over a pixel grid.
struct DepthModel {
  size_t pixels = 80;          // valid pixels per frame, about (grid stride chosen to match)
  double jump_ratio = 0.05;    // a range step to a grid neighbour above this fraction: flying pixel
  double sigma_per_m = 0.01;   // hit noise added per metre of range (in quadrature to beam.sigma_hit)
};

// Global localisation (hypotheses.hpp): while the filter weighs coarse (after a uniform prior, or
// not tracking), the `count` best distinct modes of the cloud are refined against the mesh each
// round, and those that fit are planted back as tight clouds. A sparse prior has no particle
// within centimetres of the truth, and without this the fine weighting that follows picks the
// mode with the luckiest particle, not the place that fits best.
// Scan screening (scan_screen.hpp): each global round, free-floor positions x headings scored
// on a 2D distance transform by the round's level beams; the best distinct ones are refined with
// the cloud's modes.
struct ScanScreenConfig {
  size_t keep = 24;              // candidates refined per round (0: screening off)
  size_t positions = 20000;      // free-floor places, drawn once
  size_t headings = 72;          // per place, evenly spaced (5 deg)
  size_t beams_per_scan = 30;    // level beams of each scan, evenly spread
  double truncate = 0.3;         // m: an endpoint farther from a wall costs this, squared
  double resolution = 0.1;       // m: cells of the distance transform
};

struct GlobalHypotheses {
  size_t count = 24;               // modes refined per round (0: off)
  double separation = 0.5;         // m: a mode is this far from the better ones ...
  double separation_yaw = 0.35;    // ... or turned by this much (rad)
  size_t particles = 50;           // planted per refined mode
  double spread_xy = 0.02;         // m: std of the planted cloud
  double spread_yaw = 0.01;        // rad
  double min_inlier_ratio = 0.6;   // refined fits with fewer inliers are dropped ...
  double ratio_margin = 0.1;       // ... and those more than this below the best one
  // Places tracked over the global rounds (hypotheses.hpp, TrackedPlace): the filter commits only
  // when every other place is at least `lead` behind the leader in summed evidence (inlier share
  // times the residual's likelihood; a newcomer joins `lead` behind); places more than `drop`
  // behind are forgotten.
  double lead = 0.2;
  double drop = 0.6;
  double max_correction = 0.6;     // m: how far the refinement may move a mode
  double max_correction_yaw = 0.3; // rad
  size_t beams_per_scan = 60;      // valid beams per scan in the refinement
  size_t fresh = 10000;            // uniform particles added after each coarse round (new candidates)
  ScanScreenConfig screen;         // more candidates, from the scans themselves
};

// Lost, or only hidden by people and clutter? (fit_check.hpp) After each round the estimate's
// beams are cast in the map; a round in which more than max_seen_through of them end beyond the
// map's surface (seen through a wall) contradicts the estimate. Only such rounds inject
// particles, and only those that the refinement could not pin either count towards sensor
// resetting: the likelihood level alone varies with map error, people and places, and on real
// logs fired the recovery while the track was fine.
struct FitCheck {
  double tolerance = 0.3;          // m: a beam this much beyond the map's surface saw through it
  double max_seen_through = 0.25;  // share of the round's beams
  size_t beams_per_scan = 60;      // per frame of the round, evenly spread (0: all)
  // A frame whose longer beams end on a surface behind, at least this share of them, went past
  // obstacles the map holds and are gone (fit_check.hpp); above 1: off.
  double past_share = 0.8;
  // Map fit: the share of the beams the map explains at the estimate (within tolerance),
  // smoothed over rounds (weight of the newest: smoothing). Below min_explained the scans do
  // not fit the map (a wrong map, a wrong building, a far wrong pose): never tracking. Real logs
  // at the aligned pose: per scan p01 0.41-0.74 (polyloc eval carmen --json, fit_check.explained_aligned).
  double min_explained = 0.35;
  double smoothing = 0.3;
};

struct MclConfig {
  int dof = 3;                      // 3: x, y, yaw on the floor; 6: full pose
  std::string model = "beam";       // scanners, lidar: beam | likelihood_field | plane_fragments
  std::string depth_model = "depth"; // depth cameras: depth | beam | likelihood_field | none
  // Rig sensors the filter weighs, by name (empty: all). A 2D grid predicts only level planar
  // scanners, so a grid2d filter lists those; the others stay in the rig for VRS and tracking.
  std::vector<std::string> sensors;
  // Map representation the particles are weighed against (raycast/factory.hpp: embree, bsp,
  // grid2d, distance3d, octomap). The floor under particles and free-space sampling stay on the
  // mesh (Embree): a 2D grid has no floor to stand on.
  std::string caster = "embree";
  double caster_resolution = 0.05;  // m: cells / voxels / nodes of grid2d, distance3d, octomap
  // m above the floor where grid2d slices the map; NaN: the lowest level scanner the filter weighs
  double caster_height = std::numeric_limits<double>::quiet_NaN();
  // caster gpu: the EGL platforms to try (surfaceless, device, default), and what happens when
  // no GPU can be used or one fails while running: "none" = an error naming what is missing,
  // "embree" = a warning, then the CPU caster.
  std::string gpu_platforms = "surfaceless,device,default";
  std::string gpu_fallback = "none";
  size_t particles = 2000;          // initial count (tracking)
  // KLD-sampling bounds. A tracking cloud occupies few KLD bins, so the lower bound is what it
  // gets: with scans a metre or two apart the prior spreads over 10 cm and 2 deg, and 500
  // particles put too few near a likelihood a few centimetres wide.
  size_t min_particles = 2000;
  size_t max_particles = 20000;
  size_t global_particles = 20000;  // for global localisation
  bool kld = true;
  double kld_epsilon = 0.05, kld_z = 2.33;  // 99% quantile
  double kld_bin_xy = 0.2, kld_bin_yaw = 0.175;  // m, rad (10 deg)
  double resample_ess = 0.5;        // resample when ESS / N drops below this
  double alpha_slow = 0.001, alpha_fast = 0.1;  // augmented MCL (0 disables injection)
  // After a uniform prior, this many rounds are weighed coarse even when one cluster already
  // dominates: the robot moves and sees more before the filter commits to one place.
  size_t global_coarse_rounds = 5;
  // ... and more, up to this many, until the estimate is refined against the mesh and not
  // contradicted by the fit check (mcl.fit), and one place fits best: then the filter commits.
  // In a building of look-alike rooms two places may fit alike for ever (the simulated lab's
  // three labs: 30 rounds gave 46/50 global successes, 10 gave 50/50; the real logs the same).
  size_t global_max_coarse_rounds = 10;
  // Sensor resetting: after this many rounds in a row whose scans contradict the estimate
  // (mcl.fit) and that neither the refinement nor local recovery could pin, the filter starts
  // over from a uniform prior of global_particles (0 disables).
  size_t relocalize_rounds = 5;
  // A tracked estimate that jumps farther than this (m) in one round, beyond what odometry
  // moved, into a place the scans contradict, was taken over by injected particles: unless local
  // recovery finds a place near the prediction that fits, the global search starts (0: never).
  double relocalize_jump = 1.0;
  // Local recovery (sensor resetting near the prediction, Lenser and Veloso): when no particle
  // explains a round's scans, the refinement cannot pin the estimate, or it jumped, places near
  // the predicted pose (within recovery_sigmas of its position std, at least recovery_min_radius,
  // at most recovery_max_radius, on a recovery_step lattice) x the headings within
  // recovery_sigmas of its heading std (at least recovery_min_heading; every heading when nothing
  // explains the scans) are screened (scan_screen.hpp), the best refined with the cloud's modes
  // like global hypotheses, and those that fit planted: a heading or a position off by more than
  // the cloud covers (a slip, a sharp turn on bad odometry) is found again within a round, not by
  // a global reset.
  bool recovery = true;
  double recovery_sigmas = 3.0;      // radius: this many position std of the prediction ...
  double recovery_min_radius = 0.5;  // ... at least (m)
  double recovery_max_radius = 2.0;  // ... at most (m): farther is relocalisation's business
  double recovery_step = 0.1;        // m between candidate positions
  double recovery_min_heading = 0.7853981633974483;  // rad (45 deg)
  // A place recovery finds must explain at least this share of what the track explained (the
  // smoothed fit, mcl.fit): a kidnapped robot finds weak fits near its old place.
  double recovery_min_fit = 0.8;
  // Range bias (refine.range_bias): the level scanners' ranges are shortened by a bias the
  // refinements estimate (smoothed by range_bias_gain per accepted round, within
  // +-range_bias_max m) before anything weighs them: a map whose walls stand proud of the
  // surfaces (an extruded grid) then fits the scans unshifted. false: no bias.
  bool range_bias = true;
  double range_bias_gain = 0.2;
  double range_bias_max = 0.15;
  // A published pose more than this (m) from the previous one moved by odometry is not tracking:
  // the status says the pose jumped (counted in `jumps`). 0: off.
  double max_jump = 0.5;
  // m: a pose is published tracking only while its carried covariance puts the truth within this
  // radius at 99 % (3.03 std along its worst axis): what `tracking` promises a controller. The
  // std threshold uncertain_xy alone allowed 0.9 m at 3 std; along a corridor a frame with a
  // 0.25 m std was published tracking 0.54 m off (real logs, infinite-corridor). 0: off.
  double tracking_radius = 0.5;
  // A refined pose whose innovation against the prediction (the last pose moved by odometry;
  // covariance: the tracked pose's carried over the step plus the fit's) exceeds this
  // chi-square value (3 dof; 16.27: 99.9 %) is not tracking: the fit or the odometry is wrong,
  // the round cannot tell which (`inconsistent` counter). 0: off.
  double innovation_gate = 16.27;
  // Std (m, rad) added to the gate's innovation covariance: what neither the fit's covariance
  // (from the scan's curvature: millimetres in a room) nor the odometry model carries (map
  // error, bumps, beams that are not independent). Without it a 2 cm disagreement in a
  // simulated lab failed the gate on 3 % of the rounds.
  double innovation_floor_xy = 0.03;
  double innovation_floor_yaw = 0.0174532925199433;  // rad (1 deg)
  size_t beams_per_scan = 60;       // per sensor per update
  // Tempering by beam count: a frame's summed log-likelihood counts as that of this many
  // independent beams (scaled by effective_beams / beams used, when fewer than that are used).
  // Beams of one scan are not independent: a map a few centimetres off, or a person, biases
  // neighbouring beams alike, and weighing 60 of them as independent collapses the cloud onto its
  // luckiest particle (real logs: ESS ~1 of 500). 0: no tempering by count. Applies to the
  // beam, depth and likelihood-field models while tracking (coarse weighting has its own).
  double effective_beams = 18;
  std::string subsample = "uniform";  // uniform | random
  double update_min_distance = 0.05;  // m travelled before the next update ...
  double update_min_angle = 0.05;     // ... or rad turned
  double round_timeout = 0.25;      // s: a round of sensor frames still open after this is closed
  // Particles whose body (at body_height) is closer than `clearance` to a surface get zero
  // weight. Not a key: loadConfig sets it from the robot section, the footprint's inscribed
  // radius (robot.radius when round) less clearance_margin, so that one robot size rules.
  double clearance = 0.1;
  // m: how far the map's surfaces may lie in front of the true ones (an extruded grid's walls
  // stand up to a cell proud, SLAM maps bend by centimetres): a robot passing close to a wall
  // must not find its particles blocked.
  double clearance_margin = 0.15;
  double body_height = 0.4;         // m above base_link where the clearance above is checked
  // Blocked particles are zeroed only while they hold at most this share of the weight: more
  // means the robot stands where the map says it cannot (passing close to furniture).
  double blocked_max_mass = 0.5;
  double uncertain_xy = 0.3;        // m: position std above this (or a weak dominant cluster)
  double uncertain_yaw = 0.2;       // rad   ... gives status Uncertain
  MotionNoise motion;
  BeamModel beam;
  RefineConfig refine;
  GlobalHypotheses hypotheses;
  DepthModel depth;
  LikelihoodField likelihood_field;
  PlaneFragments plane_fragments;
  FitCheck fit;
  uint64_t seed = 1;
  int threads = 0;                  // 0 = all cores
};

}  // namespace polyloc
