#include <polyloc/depth/config_yaml.hpp>

namespace polyloc {

DepthFilterConfig parseDepthFilterConfig(ConfigMap m) {
  DepthFilterConfig c;
  auto intIn = [](ConfigMap& s, const char* key, int def, int lo, int hi) {
    return int(s.getCount(key, size_t(def), size_t(lo), size_t(hi)));
  };
  if (m.has("validity")) {
    ConfigMap s = m.map("validity");
    DepthValidity& v = c.validity;
    if (s.has("range_min")) v.range_min = s.getDouble("range_min", 0, 0, 1e3);
    if (s.has("range_max")) v.range_max = s.getDouble("range_max", 0, 0, 1e3);
    if (v.range_min && v.range_max && *v.range_max <= *v.range_min) s.value("range_max").fail("must be > range_min");
    v.amplitude_min = s.getDouble("amplitude_min", v.amplitude_min, 0, 1e12);
    s.finish();
  }
  if (m.has("jump_edge")) {
    ConfigMap s = m.map("jump_edge");
    JumpEdgeFilter& j = c.jump_edge;
    j.enabled = s.getBool("enabled", j.enabled);
    j.min_angle = s.getAngle("min_angle", j.min_angle);
    if (!(j.min_angle >= 0 && j.min_angle < 1.5707963267948966)) s.value("min_angle").fail("must be in [0, 90) deg");
    j.mode = s.getChoice("mode", j.mode, {"between", "any"});
    j.neighbours = intIn(s, "neighbours", j.neighbours, 4, 8);
    if (j.neighbours != 4 && j.neighbours != 8) s.value("neighbours").fail("must be 4 or 8");
    s.finish();
  }
  if (m.has("confidence")) {
    ConfigMap s = m.map("confidence");
    ConfidenceFilter& f = c.confidence;
    f.enabled = s.getBool("enabled", f.enabled);
    f.prediction = s.getChoice("prediction", f.prediction, {"slope", "neighbour"});
    f.iterations = intIn(s, "iterations", f.iterations, 0, 100);
    f.reach = intIn(s, "reach", f.reach, 1, 16);
    f.sigma = s.getDouble("sigma", f.sigma, 1e-3, 1e3);
    f.noise = s.getDouble("noise", f.noise, 1e-6, 10);
    f.noise_per_m = s.getDouble("noise_per_m", f.noise_per_m, 0, 10);
    f.noise_per_m2 = s.getDouble("noise_per_m2", f.noise_per_m2, 0, 10);
    f.sigma_c = s.getDouble("sigma_c", f.sigma_c, 1e-12, 1e6);
    f.threshold = s.getDouble("threshold", f.threshold, 0, 1);
    f.min_support = intIn(s, "min_support", f.min_support, 1, 12);
    f.colour = s.getChoice("colour", f.colour, {"auto", "rgb", "amplitude", "none"});
    s.finish();
  }
  if (m.has("smoothing")) {
    ConfigMap s = m.map("smoothing");
    DepthSmoothing& f = c.smoothing;
    f.method = s.getChoice("method", f.method, {"none", "median", "bilateral"});
    f.size = intIn(s, "size", f.size, 1, 15);
    if (f.method == "median" && f.size != 3 && f.size != 5) s.value("size").fail("must be 3 or 5 for the median (OpenCV on float images)");
    f.sigma_depth = s.getDouble("sigma_depth", f.sigma_depth, 1e-6, 100);
    f.sigma_space = s.getDouble("sigma_space", f.sigma_space, 1e-3, 100);
    f.max_change = s.getDouble("max_change", f.max_change, 0, 100);
    s.finish();
  }
  m.finish();
  return c;
}

}  // namespace polyloc
