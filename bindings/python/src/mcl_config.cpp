// MclConfig and its nested sections, every field read-write under its YAML key (angles in
// radians here, degrees in YAML). MclConfig.from_yaml parses an `mcl:` mapping as the config does.
#include "common.hpp"

#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/config_yaml.hpp>

#include <pybind11/stl.h>

namespace polyloc::py {

// Every field of struct T under its own name.
#define POLYLOC_RW(f) .def_readwrite(#f, &T::f)

void bindMclConfig(pb::module_& m) {
  {
    using T = MotionNoise;
    auto c = pb::class_<T>(m, "MotionNoise", "motion: odometry noise (Thrun alpha1..4), 6-DoF diffusion").def(pb::init<>());
    c POLYLOC_RW(alpha1) POLYLOC_RW(alpha2) POLYLOC_RW(alpha3) POLYLOC_RW(alpha4) POLYLOC_RW(z_per_m)
        POLYLOC_RW(roll_pitch_per_m) POLYLOC_RW(omni) POLYLOC_RW(outlier_ratio) POLYLOC_RW(outlier_scale) POLYLOC_RW(recovery_scale);
  }
  {
    using T = BeamModel;
    auto c = pb::class_<T>(m, "BeamModel", "beam: the beam model mixture").def(pb::init<>());
    c POLYLOC_RW(sigma_hit) POLYLOC_RW(z_hit) POLYLOC_RW(z_short) POLYLOC_RW(z_max) POLYLOC_RW(z_rand)
        POLYLOC_RW(lambda_short) POLYLOC_RW(window_sigmas) POLYLOC_RW(window_min) POLYLOC_RW(log_scale)
        POLYLOC_RW(coarse_sigma_hit) POLYLOC_RW(coarse_log_scale);
  }
  {
    using T = LikelihoodField;
    auto c = pb::class_<T>(m, "LikelihoodField", "likelihood_field: endpoint-to-surface model").def(pb::init<>());
    c POLYLOC_RW(sigma_hit) POLYLOC_RW(z_hit) POLYLOC_RW(z_rand) POLYLOC_RW(resolution) POLYLOC_RW(max_distance)
        POLYLOC_RW(log_scale);
  }
  {
    using T = PlaneFragments;
    auto c = pb::class_<T>(m, "PlaneFragments", "plane_fragments: line and surface-patch model").def(pb::init<>());
    c POLYLOC_RW(split_threshold) POLYLOC_RW(min_points) POLYLOC_RW(min_length) POLYLOC_RW(max_gap)
        POLYLOC_RW(intersect_tolerance) POLYLOC_RW(extent_margin) POLYLOC_RW(min_angle)
        POLYLOC_RW(sigma_distance) POLYLOC_RW(sigma_angle) POLYLOC_RW(z_hit) POLYLOC_RW(z_rand)
        POLYLOC_RW(window) POLYLOC_RW(max_age) POLYLOC_RW(max_fragments) POLYLOC_RW(log_scale);
  }
  {
    using T = RefineConfig;
    auto c = pb::class_<T>(m, "RefineConfig", "refine: point-to-plane refinement of the estimate").def(pb::init<>());
    c POLYLOC_RW(enabled) POLYLOC_RW(iterations) POLYLOC_RW(beams_per_scan) POLYLOC_RW(max_correspondence)
        POLYLOC_RW(huber) POLYLOC_RW(min_step) POLYLOC_RW(max_final_step) POLYLOC_RW(min_correspondences)
        POLYLOC_RW(max_correction) POLYLOC_RW(max_correction_yaw) POLYLOC_RW(min_inlier_ratio)
        POLYLOC_RW(cast_margin) POLYLOC_RW(dof) POLYLOC_RW(depth_cameras);
  }
  {
    using T = DepthModel;
    auto c = pb::class_<T>(m, "DepthModel", "depth: the depth-camera model").def(pb::init<>());
    c POLYLOC_RW(pixels) POLYLOC_RW(jump_ratio) POLYLOC_RW(sigma_per_m);
  }
  {
    using T = GlobalHypotheses;
    auto c = pb::class_<T>(m, "GlobalHypotheses", "hypotheses: refined modes in global localisation").def(pb::init<>());
    c POLYLOC_RW(count) POLYLOC_RW(separation) POLYLOC_RW(separation_yaw) POLYLOC_RW(particles)
        POLYLOC_RW(spread_xy) POLYLOC_RW(spread_yaw) POLYLOC_RW(min_inlier_ratio) POLYLOC_RW(ratio_margin) POLYLOC_RW(lead) POLYLOC_RW(drop)
        POLYLOC_RW(max_correction) POLYLOC_RW(max_correction_yaw) POLYLOC_RW(beams_per_scan) POLYLOC_RW(fresh);
  }
  {
    using T = FitCheck;
    auto c = pb::class_<T>(m, "FitCheck", "fit: rounds whose beams see through the map contradict the estimate").def(pb::init<>());
    c POLYLOC_RW(tolerance) POLYLOC_RW(max_seen_through) POLYLOC_RW(beams_per_scan) POLYLOC_RW(past_share);
  }
  {
    using T = MclConfig;
    auto c = pb::class_<T>(m, "MclConfig",
                           "Monte-Carlo localisation settings: the `mcl:` section, every key a field "
                           "(docs/localization.md has them with defaults). Angles in radians.")
                 .def(pb::init<>());
    c POLYLOC_RW(dof) POLYLOC_RW(model) POLYLOC_RW(depth_model) POLYLOC_RW(particles) POLYLOC_RW(min_particles)
        POLYLOC_RW(max_particles) POLYLOC_RW(global_particles) POLYLOC_RW(kld) POLYLOC_RW(kld_epsilon)
        POLYLOC_RW(kld_z) POLYLOC_RW(kld_bin_xy) POLYLOC_RW(kld_bin_yaw) POLYLOC_RW(resample_ess)
        POLYLOC_RW(alpha_slow) POLYLOC_RW(alpha_fast) POLYLOC_RW(global_coarse_rounds) POLYLOC_RW(global_max_coarse_rounds)
        POLYLOC_RW(relocalize_rounds) POLYLOC_RW(relocalize_jump)
        POLYLOC_RW(beams_per_scan) POLYLOC_RW(effective_beams) POLYLOC_RW(subsample) POLYLOC_RW(update_min_distance)
        POLYLOC_RW(update_min_angle) POLYLOC_RW(round_timeout) POLYLOC_RW(clearance) POLYLOC_RW(clearance_margin) POLYLOC_RW(body_height)
        POLYLOC_RW(blocked_max_mass) POLYLOC_RW(uncertain_xy) POLYLOC_RW(uncertain_yaw) POLYLOC_RW(motion)
        POLYLOC_RW(beam) POLYLOC_RW(refine) POLYLOC_RW(hypotheses) POLYLOC_RW(depth)
        POLYLOC_RW(likelihood_field) POLYLOC_RW(plane_fragments) POLYLOC_RW(fit) POLYLOC_RW(seed) POLYLOC_RW(threads);
    c.def_static("from_yaml", [](const std::string& text) { return parseMclConfig(ConfigMap::parse(text, "<mcl>")); },
                 pb::arg("text"), "From the YAML of an `mcl:` section: defaults for absent keys, ConfigError for bad ones.");
  }
}

#undef POLYLOC_RW

}  // namespace polyloc::py
