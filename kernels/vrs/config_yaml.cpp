#include <polyloc/vrs/config_yaml.hpp>

namespace polyloc {

const char* vrsModeName(VrsMode m) {
  switch (m) {
    case VrsMode::Direct: return "direct";
    case VrsMode::Memory: return "memory";
    case VrsMode::Both: return "both";
    case VrsMode::Off: return "off";
  }
  return "?";
}

VrsMode parseVrsMode(const ConfigValue& v) {
  const std::string s = v.asString();
  for (VrsMode m : {VrsMode::Direct, VrsMode::Memory, VrsMode::Both, VrsMode::Off})
    if (s == vrsModeName(m)) return m;
  v.fail("must be one of direct, memory, both, off (got '" + s + "')");
}

VrsConfig parseVrsConfig(ConfigMap m, double robot_height) {
  VrsConfig c;
  c.robot_height = robot_height;
  c.angle_min = m.has("angle_min") ? m.value("angle_min").asAngle() : c.angle_min;
  c.angle_max = m.has("angle_max") ? m.value("angle_max").asAngle() : c.angle_max;
  if (!(c.angle_max > c.angle_min) || c.angle_max - c.angle_min > 2 * M_PI + 1e-9)
    m.fail("vrs: need angle_min < angle_max <= angle_min + 360 deg");
  c.resolution = m.getAngle("resolution", c.resolution);
  if (!(c.resolution >= 1e-4 && c.resolution <= 0.5)) m.value("resolution").fail("must be in [0.006, 28] deg");
  c.range_max = m.getDouble("range_max", c.range_max, 0.1, 1000);
  c.floor_clearance = m.getDouble("floor_clearance", c.floor_clearance, -10, 10);
  c.floor_range_margin = m.getDouble("floor_range_margin", c.floor_range_margin, 0, 0.9);
  c.robot_height = m.getDouble("robot_height", c.robot_height, 0, 100);
  if (c.robot_height <= c.floor_clearance) m.value("robot_height").fail("must be above floor_clearance");
  c.self_margin = m.getDouble("self_margin", c.self_margin, 0, 10);
  c.max_age = m.getDouble("max_age", c.max_age, 0, 1e3);
  if (m.has("sources"))
    for (const ConfigValue& item : m.value("sources").items()) {
      ConfigMap s = item.asMap();
      VrsSource src;
      src.sensor = s.value("sensor").asString();
      src.mode = parseVrsMode(s.value("mode"));
      s.finish();
      c.sources.push_back(src);
    }
  if (m.has("cones"))
    for (const ConfigValue& item : m.value("cones").items()) {
      ConfigMap s = item.asMap();
      VrsCone cone;
      cone.name = s.value("name").asString();
      const std::vector<double> p = s.value("position").asDoubles(3);
      cone.position = Eigen::Vector3d(p[0], p[1], p[2]);
      cone.yaw = s.getAngle("yaw", cone.yaw);
      cone.pitch = s.getAngle("pitch", cone.pitch);
      cone.half_angle = s.getAngle("half_angle", cone.half_angle);
      if (!(cone.half_angle > 0 && cone.half_angle < 1.5)) s.value("half_angle").fail("must be in (0, 86] deg");
      cone.range_min = s.getDouble("range_min", cone.range_min, 0, 1000);
      cone.range_max = s.getDouble("range_max", cone.range_max, 0.01, 1000);
      if (s.has("mode")) cone.mode = parseVrsMode(s.value("mode"));
      s.finish();
      c.cones.push_back(cone);
    }
  if (m.has("memory")) {
    ConfigMap mm = m.map("memory");
    ObstacleMemoryConfig& o = c.memory;
    o.enabled = mm.getBool("enabled", o.enabled);
    o.resolution = mm.getDouble("resolution", o.resolution, 0.005, 1);
    o.cells = int(mm.getCount("cells", size_t(o.cells), 8, 8192));
    o.max_distance = mm.getDouble("max_distance", o.max_distance, 0, 100);
    o.direct_margin = mm.getDouble("direct_margin", o.direct_margin, 0, 10);
    o.lifetime = mm.getDouble("lifetime", o.lifetime, 0, 1e6);
    o.moving_speed = mm.getDouble("moving_speed", o.moving_speed, 0, 100);
    o.moving_turn_rate = mm.getAngle("moving_turn_rate", o.moving_turn_rate);
    o.delay = mm.getDouble("delay", o.delay, 0, 60);
    o.track_sigmas = mm.getDouble("track_sigmas", o.track_sigmas, 0, 100);
    o.track_radius = mm.getDouble("track_radius", o.track_radius, 0, 100);
    if (o.max_distance > 0.5 * o.resolution * o.cells)
      mm.value("max_distance").fail("must be at most half the grid (cells x resolution / 2)");
    mm.finish();
  }
  if (m.has("danger_labels")) {
    c.danger_labels.clear();
    for (const ConfigValue& v : m.value("danger_labels").items()) c.danger_labels.push_back(v.asString());
  }
  if (m.has("danger_zones"))
    for (const ConfigValue& zone : m.value("danger_zones").items()) {
      std::vector<Eigen::Vector2d> poly;
      for (const ConfigValue& corner : zone.items()) {
        const std::vector<double> xy = corner.asDoubles(2);
        poly.emplace_back(xy[0], xy[1]);
      }
      if (poly.size() < 3) zone.fail("a danger zone needs at least 3 corners");
      c.danger_zones.push_back(std::move(poly));
    }
  c.danger_resolution = m.getDouble("danger_resolution", c.danger_resolution, 0.005, 10);
  m.finish();
  return c;
}

}  // namespace polyloc

