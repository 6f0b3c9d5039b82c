#include <polyloc/mcl/config_yaml.hpp>
#include <polyloc/mcl/sensor_model.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/factory.hpp>

#include <cmath>
#include <limits>
#include <sstream>

namespace polyloc {
namespace {

// `beams_per_scan`, wherever it is a key (mcl, refine, fit, hypotheses, hypotheses.screen): one
// meaning, one range. 0 takes every valid beam; more than 100,000 is no scanner.
size_t beamsPerScan(ConfigMap& m, size_t current) { return m.getCount("beams_per_scan", current, 0, 100'000); }

}  // namespace

// A screening round scores every position at every heading (12 bytes a pair: 120 MB at most).
constexpr size_t kMaxPairs = 10'000'000;

MclConfig parseMclConfig(ConfigMap m, const Rig* rig, const MclConfig& defaults) {
  MclConfig c = defaults;
  constexpr double kBig = 1e9;
  auto count = [&](const char* key, size_t def) {
    const int64_t v = m.getInt(key, int64_t(def));
    if (v < 1 || v > 10'000'000) m.value(key).fail("must be between 1 and 10000000");
    return size_t(v);
  };
  // Every integer is range-checked as int64 before it is narrowed (2^32 + 3 must not become 3).
  c.dof = int(m.getCount("dof", size_t(c.dof), 0, 6));
  if (c.dof != 3 && c.dof != 6) m.value("dof").fail("must be 3 or 6");
  {
    std::vector<std::string> names = sensorModelNames();
    c.model = m.getChoice("model", c.model, names);
    names.push_back("none");
    c.depth_model = m.getChoice("depth_model", c.depth_model, names);
  }
  if (m.has("sensors")) {
    const ConfigValue v = m.value("sensors");
    if (!v.isSequence()) v.fail("expected a list of sensor names");
    for (const ConfigValue& item : v.items()) c.sensors.push_back(item.asString());
  }
  c.caster = m.getChoice("caster", c.caster, casterNames());
  c.caster_resolution = m.getDouble("caster_resolution", c.caster_resolution, 1e-3, 10);
  if (m.has("caster_height")) c.caster_height = m.getDouble("caster_height", 0.3, -100, 100);
  if (m.has("gpu_platforms")) {  // checked here, so --check names it, not the first GPU start
    const ConfigValue v = m.value("gpu_platforms");
    c.gpu_platforms = v.asString();
    std::string p;
    std::istringstream list(c.gpu_platforms);
    size_t n = 0;
    while (std::getline(list, p, ',')) {
      ++n;
      if (p != "surfaceless" && p != "device" && p != "default")
        v.fail("unknown EGL platform '" + p + "' (a comma-separated list of surfaceless, device, default)");
    }
    if (n == 0) v.fail("names no EGL platform (surfaceless, device, default)");
  }
  c.gpu_fallback = m.getChoice("gpu_fallback", c.gpu_fallback, {"none", "embree"});
  if (rig) {
    try {
      weighedSensors(*rig, c);
    } catch (const std::invalid_argument& e) {
      if (m.has("sensors")) m.value("sensors").fail(e.what());
      if (m.has("caster")) m.value("caster").fail(e.what());
      m.fail(e.what());
    }
  }
  c.particles = count("particles", c.particles);
  c.min_particles = count("min_particles", c.min_particles);
  c.max_particles = count("max_particles", c.max_particles);
  if (c.max_particles < c.min_particles) m.value("max_particles").fail("must be >= min_particles");
  c.global_particles = count("global_particles", c.global_particles);
  c.kld = m.getBool("kld", c.kld);
  c.kld_epsilon = m.getDouble("kld_epsilon", c.kld_epsilon, 1e-6, 1);
  c.kld_z = m.getDouble("kld_z", c.kld_z, 0, 10);
  c.kld_bin_xy = m.getDouble("kld_bin_xy", c.kld_bin_xy, 1e-3, 100);
  c.kld_bin_yaw = m.getAngle("kld_bin_yaw", c.kld_bin_yaw);
  c.resample_ess = m.getDouble("resample_ess", c.resample_ess, 0, 1);
  c.alpha_slow = m.getDouble("alpha_slow", c.alpha_slow, 0, 1);
  c.alpha_fast = m.getDouble("alpha_fast", c.alpha_fast, 0, 1);
  {
    const int64_t n = m.getInt("global_coarse_rounds", int64_t(c.global_coarse_rounds));
    if (n < 0 || n > 1'000'000) m.value("global_coarse_rounds").fail("must be between 0 and 1000000");
    c.global_coarse_rounds = size_t(n);
    c.global_max_coarse_rounds = m.getCount("global_max_coarse_rounds", std::max(c.global_max_coarse_rounds, c.global_coarse_rounds), c.global_coarse_rounds, 1'000'000);
  }
  {
    const int64_t n = m.getInt("relocalize_rounds", int64_t(c.relocalize_rounds));
    if (n < 0 || n > 1'000'000) m.value("relocalize_rounds").fail("must be between 0 (off) and 1000000");
    c.relocalize_rounds = size_t(n);
  }
  if (m.has("relocalize_threshold"))
    m.value("relocalize_threshold").fail("removed: sensor resetting follows the fit check (mcl.fit), not the likelihood level");
  c.relocalize_jump = m.getDouble("relocalize_jump", c.relocalize_jump, 0, 1e6);
  c.recovery = m.getBool("recovery", c.recovery);
  c.recovery_sigmas = m.getDouble("recovery_sigmas", c.recovery_sigmas, 0, 100);
  c.recovery_min_radius = m.getDouble("recovery_min_radius", c.recovery_min_radius, 0, 100);
  c.recovery_max_radius = m.getDouble("recovery_max_radius", c.recovery_max_radius, c.recovery_min_radius, 100);
  c.recovery_step = m.getDouble("recovery_step", c.recovery_step, 0.01, 10);
  c.recovery_min_heading = m.getAngle("recovery_min_heading", c.recovery_min_heading);
  c.recovery_min_fit = m.getDouble("recovery_min_fit", c.recovery_min_fit, 0, 1);
  c.max_jump = m.getDouble("max_jump", c.max_jump, 0, 1e6);
  c.innovation_gate = m.getDouble("innovation_gate", c.innovation_gate, 0, 1e9);
  c.innovation_floor_xy = m.getDouble("innovation_floor_xy", c.innovation_floor_xy, 0, 100);
  c.innovation_floor_yaw = m.getAngle("innovation_floor_yaw", c.innovation_floor_yaw);
  c.range_bias = m.getBool("range_bias", c.range_bias);
  c.range_bias_gain = m.getDouble("range_bias_gain", c.range_bias_gain, 0, 1);
  c.range_bias_max = m.getDouble("range_bias_max", c.range_bias_max, 0, 10);
  c.beams_per_scan = beamsPerScan(m, c.beams_per_scan);
  c.effective_beams = m.getDouble("effective_beams", c.effective_beams, 0, 1e6);
  c.subsample = m.getChoice("subsample", c.subsample, {"uniform", "random"});
  c.update_min_distance = m.getDouble("update_min_distance", c.update_min_distance, 0, kBig);
  c.update_min_angle = m.getAngle("update_min_angle", c.update_min_angle);
  c.round_timeout = m.getDouble("round_timeout", c.round_timeout, 0, 1e3);
  if (m.has("robot_radius"))
    m.value("robot_radius").fail("removed: a particle's clearance is the robot's (robot.radius or robot.footprint) "
                                 "less mcl.clearance_margin");
  c.clearance_margin = m.getDouble("clearance_margin", c.clearance_margin, 0, 100);
  c.body_height = m.getDouble("body_height", c.body_height, 0, 100);
  c.blocked_max_mass = m.getDouble("blocked_max_mass", c.blocked_max_mass, 0, 1);
  c.uncertain_xy = m.getDouble("uncertain_xy", c.uncertain_xy, 0, kBig);
  c.tracking_radius = m.getDouble("tracking_radius", c.tracking_radius, 0, kBig);
  c.uncertain_yaw = m.getAngle("uncertain_yaw", c.uncertain_yaw);
  c.seed = uint64_t(m.getCount("seed", size_t(c.seed), 0, size_t(std::numeric_limits<int64_t>::max())));
  c.threads = int(m.getCount("threads", size_t(c.threads), 0, 4096));  // 0 = all cores
  if (m.has("motion")) {
    ConfigMap n = m.map("motion");
    MotionNoise& mn = c.motion;
    mn.alpha1 = n.getDouble("alpha1", mn.alpha1, 0, 100);
    mn.alpha2 = n.getDouble("alpha2", mn.alpha2, 0, 100);
    mn.alpha3 = n.getDouble("alpha3", mn.alpha3, 0, 100);
    mn.alpha4 = n.getDouble("alpha4", mn.alpha4, 0, 100);
    mn.z_per_m = n.getDouble("z_per_m", mn.z_per_m, 0, 100);
    mn.roll_pitch_per_m = n.getAngle("roll_pitch_per_m", mn.roll_pitch_per_m);
    mn.omni = n.getChoice("drive", mn.omni ? "omni" : "differential", {"differential", "omni"}) == "omni";
    mn.outlier_ratio = n.getDouble("outlier_ratio", mn.outlier_ratio, 0, 1);
    mn.outlier_scale = n.getDouble("outlier_scale", mn.outlier_scale, 1, 1000);
    mn.recovery_scale = n.getDouble("recovery_scale", mn.recovery_scale, 1, 1000);
    if (n.has("adapt")) {
      ConfigMap a = n.map("adapt");
      OdometryNoiseAdapt& ad = mn.adapt;
      ad.enabled = a.getBool("enabled", ad.enabled);
      ad.gain = a.getDouble("gain", ad.gain, 0, 1);
      ad.max_log_ratio = a.getDouble("max_log_ratio", ad.max_log_ratio, 0, 20);
      ad.min_scale = a.getDouble("min_scale", ad.min_scale, 0.01, 100);
      ad.max_scale = a.getDouble("max_scale", ad.max_scale, ad.min_scale, 1000);
      ad.min_step = a.getDouble("min_step", ad.min_step, 0, 100);
      ad.min_turn = a.getAngle("min_turn", ad.min_turn);
      a.finish();
    }
    n.finish();
  }
  if (m.has("depth")) {
    ConfigMap d = m.map("depth");
    DepthModel& dm = c.depth;
    dm.pixels = d.getCount("pixels", dm.pixels, 1, 10'000'000);
    dm.jump_ratio = d.getDouble("jump_ratio", dm.jump_ratio, 1e-4, 100);
    dm.sigma_per_m = d.getDouble("sigma_per_m", dm.sigma_per_m, 0, 10);
    d.finish();
  }
  if (m.has("refine")) {
    ConfigMap r = m.map("refine");
    RefineConfig& rc = c.refine;
    rc.enabled = r.getBool("enabled", rc.enabled);
    rc.iterations = int(r.getCount("iterations", size_t(rc.iterations), 1, 1000));
    rc.beams_per_scan = beamsPerScan(r, rc.beams_per_scan);
    rc.max_correspondence = r.getDouble("max_correspondence", rc.max_correspondence, 1e-4, 100);
    rc.huber = r.getDouble("huber", rc.huber, 1e-5, 100);
    rc.min_step = r.getDouble("min_step", rc.min_step, 0, 1);
    rc.max_final_step = r.getDouble("max_final_step", rc.max_final_step, 0, 1);
    rc.min_correspondences = r.getCount("min_correspondences", rc.min_correspondences, 0, 10'000'000);
    rc.max_correction = r.getDouble("max_correction", rc.max_correction, 0, 100);
    rc.max_correction_yaw = r.getAngle("max_correction_yaw", rc.max_correction_yaw);
    rc.min_inlier_ratio = r.getDouble("min_inlier_ratio", rc.min_inlier_ratio, 0, 1);
    rc.cast_margin = r.getDouble("cast_margin", rc.cast_margin, 0, 100);
    rc.search_xy = r.getDouble("search_xy", rc.search_xy, 0, 10);
    rc.search_yaw = r.getAngle("search_yaw", rc.search_yaw);
    if (rc.search_yaw < 0 || rc.search_yaw > M_PI) r.value("search_yaw").fail("must be between 0 and 180 deg");
    rc.search_beams = r.getCount("search_beams", rc.search_beams, 0, 100'000);
    rc.search_sigmas = r.getDouble("search_sigmas", rc.search_sigmas, 0, 100);
    rc.search_spread = r.getBool("search_spread", rc.search_spread);
    rc.max_search_xy = r.getDouble("max_search_xy", rc.max_search_xy, 0, 10);
    rc.max_search_yaw = r.getAngle("max_search_yaw", rc.max_search_yaw);
    if (rc.max_search_yaw < 0 || rc.max_search_yaw > M_PI) r.value("max_search_yaw").fail("must be between 0 and 180 deg");
    rc.range_bias_prior = r.getDouble("range_bias_prior", rc.range_bias_prior, 1e-4, 10);
    rc.search_step_xy = r.getDouble("search_step_xy", rc.search_step_xy, 1e-3, 10);
    rc.search_step_yaw = r.getAngle("search_step_yaw", rc.search_step_yaw);
    if (!(rc.search_step_yaw > 0)) r.value("search_step_yaw").fail("must be positive");
    rc.dof = int(r.getCount("dof", size_t(rc.dof), 0, 6));
    rc.depth_cameras = r.getBool("depth_cameras", rc.depth_cameras);
    if (rc.dof != 0 && rc.dof != 3 && rc.dof != 6) r.value("dof").fail("must be 0 (the filter's), 3 or 6");
    r.finish();
  }
  if (m.has("fit")) {
    ConfigMap f = m.map("fit");
    FitCheck& fc = c.fit;
    fc.tolerance = f.getDouble("tolerance", fc.tolerance, 1e-3, 100);
    fc.max_seen_through = f.getDouble("max_seen_through", fc.max_seen_through, 0, 1);
    fc.min_explained = f.getDouble("min_explained", fc.min_explained, 0, 1);
    fc.smoothing = f.getDouble("smoothing", fc.smoothing, 1e-3, 1);
    fc.past_share = f.getDouble("past_share", fc.past_share, 0, 2);
    fc.beams_per_scan = beamsPerScan(f, fc.beams_per_scan);
    f.finish();
  }
  if (m.has("hypotheses")) {
    ConfigMap h = m.map("hypotheses");
    GlobalHypotheses& gh = c.hypotheses;
    gh.count = h.getCount("count", gh.count, 0, 10'000);
    gh.separation = h.getDouble("separation", gh.separation, 0, 100);
    gh.separation_yaw = h.getAngle("separation_yaw", gh.separation_yaw);
    gh.particles = h.getCount("particles", gh.particles, 1, 100'000);
    gh.spread_xy = h.getDouble("spread_xy", gh.spread_xy, 0, 10);
    gh.spread_yaw = h.getAngle("spread_yaw", gh.spread_yaw);
    gh.min_inlier_ratio = h.getDouble("min_inlier_ratio", gh.min_inlier_ratio, 0, 1);
    gh.ratio_margin = h.getDouble("ratio_margin", gh.ratio_margin, 0, 1);
    gh.lead = h.getDouble("lead", gh.lead, 0, 100);
    gh.drop = h.getDouble("drop", gh.drop, 0, 1000);
    gh.max_correction = h.getDouble("max_correction", gh.max_correction, 0, 100);
    gh.max_correction_yaw = h.getAngle("max_correction_yaw", gh.max_correction_yaw);
    gh.beams_per_scan = beamsPerScan(h, gh.beams_per_scan);
    gh.fresh = h.getCount("fresh", gh.fresh, 0, 10'000'000);
    if (h.has("screen")) {
      ConfigMap sm = h.map("screen");
      ScanScreenConfig& sc = gh.screen;
      sc.keep = sm.getCount("keep", sc.keep, 0, 10'000);
      sc.positions = sm.getCount("positions", sc.positions, 1, 10'000'000);
      sc.headings = sm.getCount("headings", sc.headings, 1, 3600);
      if (sc.positions * sc.headings > kMaxPairs)
        sm.fail("positions x headings = " + std::to_string(sc.positions * sc.headings) + " exceeds " +
                std::to_string(kMaxPairs) + " (the memory budget of one screening round, 12 bytes a pair)");
      sc.beams_per_scan = beamsPerScan(sm, sc.beams_per_scan);
      sc.truncate = sm.getDouble("truncate", sc.truncate, 1e-3, 100);
      sc.resolution = sm.getDouble("resolution", sc.resolution, 0.01, 10);
      sm.finish();
    }
    h.finish();
  }
  {  // Local recovery screens a (2n + 1)^2 lattice, n = max_radius / step, at up to screen.headings.
    const double n = std::ceil(c.recovery_max_radius / c.recovery_step);
    const double pairs = (2 * n + 1) * (2 * n + 1) * double(c.hypotheses.screen.headings);
    if (pairs > double(kMaxPairs)) {
      const std::string why = "recovery_max_radius / recovery_step gives a lattice of " + std::to_string(size_t((2 * n + 1) * (2 * n + 1))) +
                              " places x " + std::to_string(c.hypotheses.screen.headings) + " headings, beyond " +
                              std::to_string(kMaxPairs) + " (the memory budget of one screening round)";
      if (m.has("recovery_step")) m.value("recovery_step").fail(why);
      if (m.has("recovery_max_radius")) m.value("recovery_max_radius").fail(why);
      m.fail(why);
    }
  }
  if (m.has("beam")) {
    ConfigMap b = m.map("beam");
    BeamModel& bm = c.beam;
    bm.sigma_hit = b.getDouble("sigma_hit", bm.sigma_hit, 1e-4, 100);
    bm.z_hit = b.getDouble("z_hit", bm.z_hit, 0, 1);
    bm.z_short = b.getDouble("z_short", bm.z_short, 0, 1);
    bm.z_max = b.getDouble("z_max", bm.z_max, 0, 1);
    bm.z_rand = b.getDouble("z_rand", bm.z_rand, 1e-9, 1);
    bm.lambda_short = b.getDouble("lambda_short", bm.lambda_short, 1e-6, 1000);
    bm.window_sigmas = b.getDouble("window_sigmas", bm.window_sigmas, 0, 1000);
    bm.window_min = b.getDouble("window_min", bm.window_min, 0, 1000);
    bm.log_scale = b.getDouble("log_scale", bm.log_scale, 1e-6, 1);
    bm.coarse_sigma_hit = b.getDouble("coarse_sigma_hit", bm.coarse_sigma_hit, 1e-4, 100);
    bm.coarse_log_scale = b.getDouble("coarse_log_scale", bm.coarse_log_scale, 1e-6, 1);
    b.finish();
  }
  if (m.has("likelihood_field")) {
    ConfigMap b = m.map("likelihood_field");
    LikelihoodField& lf = c.likelihood_field;
    lf.sigma_hit = b.getDouble("sigma_hit", lf.sigma_hit, 1e-4, 100);
    lf.z_hit = b.getDouble("z_hit", lf.z_hit, 0, 1);
    lf.z_rand = b.getDouble("z_rand", lf.z_rand, 1e-9, 1);
    lf.resolution = b.getDouble("resolution", lf.resolution, 0.005, 10);
    lf.max_distance = b.getDouble("max_distance", lf.max_distance, 1e-3, 100);
    lf.log_scale = b.getDouble("log_scale", lf.log_scale, 1e-6, 1);
    b.finish();
  }
  if (m.has("plane_fragments")) {
    ConfigMap f = m.map("plane_fragments");
    PlaneFragments& pf = c.plane_fragments;
    auto fcount = [&](const char* key, size_t def, int64_t lo) {
      const int64_t v = f.getInt(key, int64_t(def));
      if (v < lo || v > 1'000'000) f.value(key).fail("must be between " + std::to_string(lo) + " and 1000000");
      return size_t(v);
    };
    pf.split_threshold = f.getDouble("split_threshold", pf.split_threshold, 1e-4, 10);
    pf.min_points = fcount("min_points", pf.min_points, 2);
    pf.min_length = f.getDouble("min_length", pf.min_length, 0, 100);
    pf.max_gap = f.getDouble("max_gap", pf.max_gap, 1e-3, 100);
    pf.intersect_tolerance = f.getDouble("intersect_tolerance", pf.intersect_tolerance, 1e-4, 10);
    pf.extent_margin = f.getDouble("extent_margin", pf.extent_margin, 0, 10);
    pf.min_angle = f.getAngle("min_angle", pf.min_angle);
    if (!(pf.min_angle > 0 && pf.min_angle < 1.5707963267948966)) f.value("min_angle").fail("must be in (0, 90) deg");
    pf.sigma_distance = f.getDouble("sigma_distance", pf.sigma_distance, 1e-4, 100);
    pf.sigma_angle = f.getAngle("sigma_angle", pf.sigma_angle);
    if (!(pf.sigma_angle > 0 && pf.sigma_angle <= 3.141592653589793)) f.value("sigma_angle").fail("must be in (0, 180] deg");
    pf.z_hit = f.getDouble("z_hit", pf.z_hit, 0, 1);
    pf.z_rand = f.getDouble("z_rand", pf.z_rand, 1e-9, 1);
    pf.window = f.getDouble("window", pf.window, 1e-3, 100);
    pf.max_age = f.getDouble("max_age", pf.max_age, 0, 3600);
    pf.max_fragments = fcount("max_fragments", pf.max_fragments, 0);
    pf.log_scale = f.getDouble("log_scale", pf.log_scale, 1e-6, 1);
    f.finish();
  }
  m.finish();
  return c;
}

}  // namespace polyloc
