#include <polyloc/mcl/config_yaml.hpp>
#include <polyloc/mcl/sensor_model.hpp>

#include <limits>

namespace polyloc {

MclConfig parseMclConfig(ConfigMap m) {
  MclConfig c;
  constexpr double kBig = 1e9;
  auto count = [&](const char* key, size_t def) {
    const int64_t v = m.getInt(key, int64_t(def));
    if (v < 1 || v > 10'000'000) m.value(key).fail("must be between 1 and 10000000");
    return size_t(v);
  };
  c.dof = int(m.getInt("dof", c.dof));
  if (c.dof != 3 && c.dof != 6) m.value("dof").fail("must be 3 or 6");
  {
    std::vector<std::string> names = sensorModelNames();
    c.model = m.getChoice("model", c.model, names);
    names.push_back("none");
    c.depth_model = m.getChoice("depth_model", c.depth_model, names);
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
  c.beams_per_scan = count("beams_per_scan", c.beams_per_scan);
  c.subsample = m.getChoice("subsample", c.subsample, {"uniform"});
  c.update_min_distance = m.getDouble("update_min_distance", c.update_min_distance, 0, kBig);
  c.update_min_angle = m.getAngle("update_min_angle", c.update_min_angle);
  c.robot_radius = m.getDouble("robot_radius", c.robot_radius, 0, 100);
  c.body_height = m.getDouble("body_height", c.body_height, 0, 100);
  c.uncertain_xy = m.getDouble("uncertain_xy", c.uncertain_xy, 0, kBig);
  c.uncertain_yaw = m.getAngle("uncertain_yaw", c.uncertain_yaw);
  c.seed = uint64_t(m.getInt("seed", int64_t(c.seed)));
  c.threads = int(m.getInt("threads", c.threads));
  if (c.threads < 0) m.value("threads").fail("must be >= 0 (0 = all cores)");
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
    n.finish();
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
    b.finish();
  }
  m.finish();
  return c;
}

}  // namespace polyloc
