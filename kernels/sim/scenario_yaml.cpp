// loadScenario: the scenario YAML (docs/simulation.md). Every key is read through ConfigMap, so
// unknown keys and bad values are errors naming file, line and key.
#include <polyloc/sim/scenario.hpp>

#include <cmath>
#include <filesystem>
#include <limits>

namespace polyloc {

namespace {

Eigen::Vector2d point(const ConfigValue& v) {
  const std::vector<double> p = v.asDoubles(2);
  return {p[0], p[1]};
}

Waypoint parseWaypoint(const ConfigValue& v) {
  Waypoint w;
  if (v.isSequence()) {
    const std::vector<ConfigValue> items = v.items();
    if (items.size() != 2 && items.size() != 3)
      v.fail("a waypoint is [x, y], [x, y, heading] or {x, y, heading, wait, stop}");
    w.p = {items[0].asDouble(), items[1].asDouble()};
    if (items.size() == 3) w.heading = items[2].asAngle();
    return w;
  }
  ConfigMap m = v.asMap();
  w.p = {m.value("x").asDouble(), m.value("y").asDouble()};
  if (m.has("heading")) w.heading = m.value("heading").asAngle();
  w.wait = m.getDouble("wait", 0.0, 0.0, 1e6);
  w.stop = m.getBool("stop", false);
  m.finish();
  return w;
}

RouteSpec parseRoute(ConfigMap m) {
  RouteSpec r;
  const ConfigValue list = m.value("waypoints");
  for (const ConfigValue& v : list.items()) r.waypoints.push_back(parseWaypoint(v));
  if (r.waypoints.empty()) list.fail("a route needs at least one waypoint");
  constexpr double kBig = 1e6;
  r.max_speed = m.getDouble("max_speed", r.max_speed, 1e-3, 20);
  r.max_acceleration = m.getDouble("max_acceleration", r.max_acceleration, 1e-3, 20);
  r.max_lateral_acceleration = m.getDouble("max_lateral_acceleration", r.max_lateral_acceleration, 1e-3, 20);
  r.max_yaw_rate = m.getAngle("max_yaw_rate", r.max_yaw_rate);
  r.max_yaw_acceleration = m.getAngle("max_yaw_acceleration", r.max_yaw_acceleration);
  if (!(r.max_yaw_rate > 0)) m.value("max_yaw_rate").fail("must be positive");
  if (!(r.max_yaw_acceleration > 0)) m.value("max_yaw_acceleration").fail("must be positive");
  r.spacing = m.getDouble("spacing", r.spacing, 0.01, kBig);
  r.start_pause = m.getDouble("start_pause", r.start_pause, 0.0, kBig);
  if (m.has("heading")) r.heading = m.value("heading").asAngle();
  m.finish();
  return r;
}

FloorSpec parseFloor(ConfigMap m) {
  FloorSpec f;
  f.follow = m.getBool("follow", f.follow);
  f.unevenness = m.getDouble("unevenness", f.unevenness, 0.0, 0.2);
  f.wavelength = m.getDouble("wavelength", f.wavelength, 0.05, 100.0);
  f.probe_height = m.getDouble("probe_height", f.probe_height, -1e4, 1e4);
  if (m.has("labels")) {
    f.labels.clear();
    for (const ConfigValue& v : m.value("labels").items()) f.labels.push_back(v.asString());
  }
  if (m.has("contact_points")) {
    const ConfigValue v = m.value("contact_points");
    for (const ConfigValue& p : v.items()) f.contact_points.push_back(point(p));
    if (f.contact_points.size() < 3) v.fail("needs at least 3 contact points");
  }
  m.finish();
  return f;
}

PersonSpec parsePerson(ConfigMap m, size_t index) {
  PersonSpec p;
  p.name = m.getString("name", "person" + std::to_string(index + 1));
  if (m.has("waypoints") == m.has("circle")) m.fail("a person needs either waypoints or circle");
  if (m.has("waypoints")) {
    const ConfigValue v = m.value("waypoints");
    for (const ConfigValue& w : v.items()) p.waypoints.push_back(point(w));
    if (p.waypoints.empty()) v.fail("needs at least one waypoint");
  } else {
    ConfigMap c = m.value("circle").asMap();
    p.circle = true;
    const ConfigValue centre = c.value("centre");
    if (centre.isScalar()) {
      if (centre.asString() != "robot") centre.fail("expected [x, y] or robot");
      p.around_robot = true;
    } else {
      p.centre = point(centre);
    }
    p.radius = c.getDouble("radius", p.radius, 0.1, 1e3);
    c.finish();
  }
  p.loop = m.getBool("loop", p.loop);
  p.speed = m.getDouble("speed", p.speed, -10.0, 10.0);
  p.start = m.getDouble("start", p.start, 0.0, 1e9);
  p.end = m.getDouble("end", p.end, 0.0, std::numeric_limits<double>::max());
  p.offset = m.getDouble("offset", p.offset, -1e9, 1e9);
  p.z = m.getDouble("z", p.z, -1e4, 1e4);
  p.height = m.getDouble("height", p.height, 0.5, 2.5);
  if (p.end <= p.start) m.fail("end must be after start");
  m.finish();
  return p;
}

// A `seed` key, when given (sections: their own seed, default the scenario's).
std::optional<uint64_t> optionalSeed(ConfigMap& m) {
  if (!m.has("seed")) return std::nullopt;
  const ConfigValue v = m.value("seed");
  if (v.asInt() < 0) v.fail("must not be negative");
  return static_cast<uint64_t>(v.asInt());
}

ChairMoves parseChairs(ConfigMap m) {
  ChairMoves c;
  c.label = m.getString("label", c.label);
  if (m.has("moves")) {
    for (const ConfigValue& v : m.value("moves").items()) {
      ConfigMap mv = v.asMap();
      ChairMove move;
      move.where = v.where();
      move.from = point(mv.value("from"));
      move.to = point(mv.value("to"));
      move.rotate = mv.getAngle("rotate", 0.0);
      mv.finish();
      c.moves.push_back(move);
    }
  }
  c.random_shift = m.getDouble("random_shift", 0.0, 0.0, 10.0);
  c.random_rotation = m.getAngle("random_rotation", 0.0);
  c.seed = optionalSeed(m);
  m.finish();
  return c;
}

WorldSpec parseWorld(ConfigMap m) {
  WorldSpec w;
  if (m.has("mesh")) {
    const ConfigValue v = m.value("mesh");
    w.mesh = m.resolvePath(v.asString());
    if (!std::filesystem::is_regular_file(w.mesh)) v.fail("mesh file '" + w.mesh + "' does not exist");
  }
  if (m.has("remove"))
    for (const ConfigValue& v : m.value("remove").items()) {
      ConfigMap r = v.asMap();
      w.remove.push_back({r.value("label").asString(), point(r.value("at")), v.where()});
      r.finish();
    }
  if (m.has("add"))
    for (const ConfigValue& v : m.value("add").items()) {
      ConfigMap a = v.asMap();
      WorldBox b;
      const ConfigValue bv = a.value("box");
      const std::vector<double> c = bv.asDoubles(6);
      b.lo = {c[0], c[1], c[2]}, b.hi = {c[3], c[4], c[5]};
      if (!(b.lo.array() < b.hi.array()).all()) bv.fail("a box is [x0, y0, z0, x1, y1, z1] with x0 < x1, y0 < y1, z0 < z1");
      b.yaw = a.getAngle("yaw", 0.0);
      b.label = a.getString("label", b.label);
      a.finish();
      w.add.push_back(b);
    }
  w.wall_offset = m.getDouble("wall_offset", w.wall_offset, 0.0, 1.0);
  if (m.has("offset_labels")) {
    w.offset_labels.clear();
    for (const ConfigValue& v : m.value("offset_labels").items()) w.offset_labels.push_back(v.asString());
  }
  if (m.has("clutter")) {
    ConfigMap c = m.value("clutter").asMap();
    ClutterSpec& k = w.clutter;
    k.count = static_cast<int>(c.getCount("count", 0, 0, 10000));
    if (c.has("size")) {
      const std::vector<double> v = c.value("size").asDoubles(2);
      k.size_min = v[0], k.size_max = v[1];
      if (!(0.01 <= v[0] && v[0] <= v[1] && v[1] <= 10)) c.value("size").fail("is [min, max] with 0.01 <= min <= max <= 10 m");
    }
    if (c.has("height")) {
      const std::vector<double> v = c.value("height").asDoubles(2);
      k.height_min = v[0], k.height_max = v[1];
      if (!(0.01 <= v[0] && v[0] <= v[1] && v[1] <= 10)) c.value("height").fail("is [min, max] with 0.01 <= min <= max <= 10 m");
    }
    k.route_clearance = c.getDouble("route_clearance", k.route_clearance, 0.0, 100.0);
    k.label = c.getString("label", k.label);
    c.finish();
  }
  w.subdivide = static_cast<int>(m.getCount("subdivide", 0, 0, 3));
  w.seed = optionalSeed(m);
  m.finish();
  return w;
}

void parseSensorNoise(ConfigMap m, SensorNoise& n) {
  n.sigma = m.getDouble("sigma", n.sigma, 0.0, 10.0);
  n.sigma_slope = m.getDouble("sigma_slope", n.sigma_slope, 0.0, 1.0);
  n.sigma_rel = m.getDouble("sigma_rel", n.sigma_rel, 0.0, 1.0);
  n.bias = m.getDouble("bias", n.bias, -10.0, 10.0);
  n.beam_bias = m.getDouble("beam_bias", n.beam_bias, 0.0, 1.0);
  n.angle_jitter = m.getAngle("angle_jitter", n.angle_jitter);
  if (n.angle_jitter < 0 || n.angle_jitter > 0.2) m.value("angle_jitter").fail("must be in [0, 11.5] deg");
  n.dropout = m.getDouble("dropout", n.dropout, 0.0, 1.0);
  n.max_range = m.getDouble("max_range", n.max_range, 0.0, 1.0);
  if (m.has("glass")) {
    const ConfigValue v = m.value("glass");
    try {
      n.glass = parseGlassMode(v.asString());
    } catch (const std::invalid_argument& e) {
      v.fail(e.what());
    }
  }
  n.reflection_outlier = m.getDouble("reflection_outlier", n.reflection_outlier, 0.0, 1.0);
  n.reflection_min = m.getDouble("reflection_min", n.reflection_min, 0.0, 1.0);
  n.reflection_max = m.getDouble("reflection_max", n.reflection_max, 0.0, 1.0);
  if (n.reflection_min > n.reflection_max) m.fail("reflection_min must not exceed reflection_max");
  if (m.has("specular_labels")) {
    n.specular_labels.clear();
    for (const ConfigValue& v : m.value("specular_labels").items()) n.specular_labels.push_back(v.asString());
  }
  n.flying_pixel = m.getDouble("flying_pixel", n.flying_pixel, 0.0, 1.0);
  n.flying_threshold = m.getDouble("flying_threshold", n.flying_threshold, 1e-4, 100.0);
  n.amplitude_scale = m.getDouble("amplitude_scale", n.amplitude_scale, 0.0, 1e12);
  n.amplitude_noise = m.getDouble("amplitude_noise", n.amplitude_noise, 0.0, 10.0);
  n.amplitude_min = m.getDouble("amplitude_min", n.amplitude_min, 0.0, 1e12);
  if (m.has("reflectivity")) {
    const ConfigValue v = m.value("reflectivity");
    ConfigMap r = v.asMap();
    for (auto it = v.node().begin(); it != v.node().end(); ++it) {
      const std::string label = it->first.Scalar();
      n.reflectivity[label] = r.getDouble(label, 0.5, 0.0, 10.0);
    }
  }
  m.finish();
}

NoiseSettings parseNoise(ConfigMap m, const Rig& rig) {
  NoiseSettings s;
  s.enabled = m.getBool("enabled", s.enabled);
  if (m.has("glass")) {
    const ConfigValue v = m.value("glass");
    try {
      s.glass = parseGlassMode(v.asString());
    } catch (const std::invalid_argument& e) {
      v.fail(e.what());
    }
  }
  s.max_bounces = static_cast<int>(m.getDouble("max_bounces", s.max_bounces, 0, 64));
  s.sensors = defaultSensorNoise(rig);
  if (m.has("sensors")) {
    const ConfigValue v = m.value("sensors");
    ConfigMap per = v.asMap();
    // Preset keys first (every sensor of that model), then sensor names (one sensor).
    for (int pass = 0; pass < 2; ++pass) {
      for (auto it = v.node().begin(); it != v.node().end(); ++it) {
        const std::string key = it->first.Scalar();
        const int by_name = rig.find(key);
        bool by_preset = false;
        for (const std::string& p : rig.presets) by_preset |= p == key;
        if (by_name < 0 && !by_preset)
          ConfigValue(it->first, std::make_shared<const std::string>(per.file()), per.keyPath(key))
              .fail("neither a sensor of the rig nor the preset of one");
        if (pass == 0 && by_name < 0) {
          for (size_t i = 0; i < rig.size(); ++i)
            if (rig.presets[i] == key) parseSensorNoise(per.value(key).asMap(), s.sensors[i]);
        } else if (pass == 1 && by_name >= 0) {
          parseSensorNoise(per.value(key).asMap(), s.sensors[by_name]);
        }
      }
    }
    per.finish();
  }
  m.finish();
  return s;
}

OdometrySettings parseOdometry(ConfigMap m) {
  OdometrySettings o;
  o.rate_hz = m.getDouble("rate_hz", o.rate_hz, 0.1, 10000);
  OdometryNoise& n = o.noise;
  n.alpha1 = m.getDouble("alpha1", n.alpha1, 0.0, 100.0);
  n.alpha2 = m.getDouble("alpha2", n.alpha2, 0.0, 100.0);
  n.alpha3 = m.getDouble("alpha3", n.alpha3, 0.0, 100.0);
  n.alpha4 = m.getDouble("alpha4", n.alpha4, 0.0, 100.0);
  n.slip_translation = m.getDouble("slip_translation", n.slip_translation, 0.0, 100.0);
  n.slip_rotation = m.getDouble("slip_rotation", n.slip_rotation, 0.0, 100.0);
  m.finish();
  return o;
}

// Seconds as written (an integer is exact; a decimal keeps microseconds) to nanoseconds.
int64_t parseStartTime(const ConfigValue& v) {
  const std::string s = v.asString();
  if (s.find_first_of(".eE") == std::string::npos) {
    const int64_t sec = v.asInt();
    if (sec < 0 || sec > 9000000000LL) v.fail("must be in [0, 9e9] s");
    return sec * 1000000000LL;
  }
  const double d = v.asDouble();
  if (d < 0 || d > 9e9) v.fail("must be in [0, 9e9] s");
  const int64_t sec = static_cast<int64_t>(std::floor(d));
  return sec * 1000000000LL + std::llround((d - static_cast<double>(sec)) * 1e9);
}

}  // namespace

std::vector<SensorNoise> defaultSensorNoise(const Rig& rig) {
  std::vector<SensorNoise> out;
  for (size_t i = 0; i < rig.size(); ++i) out.push_back(defaultNoise(rig.presets[i], rig.sensors[i].spec));
  return out;
}

namespace {

constexpr int kMaxBaseDepth = 8;  // base chains longer than this are a cycle

Scenario loadScenarioAt(const std::string& path, int depth) {
  ConfigMap m = ConfigMap::load(path);
  Scenario s;
  const bool derived = m.has("base");
  if (derived) {
    const ConfigValue v = m.value("base");
    const std::string file = m.resolvePath(v.asString());
    if (!std::filesystem::is_regular_file(file)) v.fail("base scenario '" + file + "' does not exist");
    if (depth >= kMaxBaseDepth) v.fail("more than 8 bases in a chain (a cycle?)");
    s = loadScenarioAt(file, depth + 1);
  }
  s.file = path;
  if (m.has("config")) {
    const ConfigValue v = m.value("config");
    const std::string file = m.resolvePath(v.asString());
    if (!std::filesystem::is_regular_file(file)) v.fail("config file '" + file + "' does not exist");
    s.config = loadConfig(file);
  } else if (!derived) {
    for (const char* key : {"map", "rig"})
      if (!m.has(key)) m.fail(std::string("missing key '") + key + "' (or give config: a polyloc configuration file)");
    applyRobot(s.config, s.config.robot);  // the defaults' VRS height and clearance are the default robot's
    s.config.vrs.robot_height = s.config.robot.height;
  }
  if (m.has("map")) s.config.map = readMapConfig(m.value("map"), m);
  if (m.has("robot")) applyRobot(s.config, parseRobot(m.value("robot").asMap()));
  if (m.has("rig")) s.config.rig = readRig(m.value("rig"), m);
  if (const auto seed = optionalSeed(m)) s.seed = *seed;
  if (m.has("start_time")) s.start_time_ns = parseStartTime(m.value("start_time"));
  s.duration = m.getDouble("duration", s.duration, 0.0, 1e7);
  // Sections: required (route) or defaulted in a scenario of its own; replaced when given in a derived one.
  if (!derived || m.has("route")) s.route = parseRoute(m.value("route").asMap());
  if (!derived || m.has("floor")) s.floor = parseFloor(m.map("floor"));
  if (m.has("people")) {
    s.people.clear();
    const std::vector<ConfigValue> items = m.value("people").items();
    for (size_t i = 0; i < items.size(); ++i) s.people.push_back(parsePerson(items[i].asMap(), i));
  }
  if (!derived || m.has("chairs")) s.chairs = parseChairs(m.map("chairs"));
  if (!derived || m.has("world")) s.world = parseWorld(m.map("world"));
  // Per-sensor noise belongs to the rig: a new rig gets its own noise section (or the defaults).
  if (!derived || m.has("noise") || m.has("rig") || m.has("config")) s.noise = parseNoise(m.map("noise"), s.config.rig);
  if (!derived || m.has("odometry")) s.odometry = parseOdometry(m.map("odometry"));
  if (m.has("navigation")) {
    ConfigMap n = m.map("navigation");
    NavigationSpec nav;
    nav.zones = n.getPath("zones", "");
    if (n.has("goals"))
      for (const ConfigValue& g : n.value("goals").items()) nav.goals.push_back(g.asString());
    nav.mission_timeout = n.getDouble("mission_timeout", nav.mission_timeout, 1.0, 1e5);
    nav.start_yaw = n.getAngle("start_yaw", nav.start_yaw);
    if (n.has("vrs_sources"))
      for (const ConfigValue& v : n.value("vrs_sources").items()) {
        ConfigMap e = v.asMap();
        const std::string sensor = e.getString("sensor", "");
        if (sensor.empty()) e.fail("missing key 'sensor'");
        nav.vrs_sources.emplace_back(sensor, e.getChoice("mode", "direct", {"direct", "memory", "both", "off"}));
        e.finish();
      }
    n.finish();
    s.navigation = nav;
  }
  m.finish();
  return s;
}

}  // namespace

Scenario loadScenario(const std::string& path) { return loadScenarioAt(path, 0); }

}  // namespace polyloc
