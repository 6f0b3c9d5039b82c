#include <polyloc/sensors/rig.hpp>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>

namespace polyloc {

int Rig::find(const std::string& sensor_name) const {
  for (size_t i = 0; i < sensors.size(); ++i)
    if (sensors[i].name == sensor_name) return static_cast<int>(i);
  return -1;
}

bool Rig::isLevelScanner(size_t i, double max_tilt) const {
  if (i >= sensors.size() || !std::holds_alternative<PlanarScannerSpec>(sensors[i].spec)) return false;
  const Eigen::Vector3d up = sensors[i].mount.rotate(Eigen::Vector3d::UnitZ());
  return up.z() > std::cos(max_tilt);
}

std::vector<std::string> rigPresetNames() { return {"lisa", "taser"}; }

Rig rigPreset(const std::string& name) {
  Rig r;
  r.name = name;
  auto mount = [](double x, double y, double z, double pitch_deg, double yaw_deg) {
    return Pose::fromXYZRPY(x, y, z, 0, deg2rad(pitch_deg), deg2rad(yaw_deg));
  };
  if (name == "lisa") {
    // Footprint x in [-0.3, 0.3], y in [-0.25, 0.25]: the S300s sit 2 cm inside the corners.
    r.add({"s300_front_left", sickS300(), mount(0.28, 0.23, 0.10, 0, 45)}, "sick_s300");
    r.add({"s300_rear_right", sickS300(), mount(-0.28, -0.23, 0.10, 0, -135)}, "sick_s300");
    r.add({"urg_front", hokuyoURG04LX(), mount(0.30, 0.0, 1.0, 40, 0)}, "hokuyo_urg04lx");
    r.add({"urg_left", hokuyoURG04LX(), mount(0.0, 0.25, 1.0, 40, 90)}, "hokuyo_urg04lx");
    r.add({"urg_rear", hokuyoURG04LX(), mount(-0.30, 0.0, 1.0, 40, 180)}, "hokuyo_urg04lx");
    r.add({"urg_right", hokuyoURG04LX(), mount(0.0, -0.25, 1.0, 40, -90)}, "hokuyo_urg04lx");
    r.add({"tof_front", pmdO3D100(), mount(0.30, 0.0, 0.75, 10, 0)}, "pmd_o3d100");
    return r;
  }
  if (name == "taser") {
    r.add({"lms_front", sickLMS200(), mount(0.33, 0.0, 0.20, 0, 0)}, "sick_lms200");
    r.add({"lms_rear", sickLMS200(), mount(-0.33, 0.0, 0.20, 0, 180)}, "sick_lms200");
    return r;
  }
  std::string known;
  for (const auto& n : rigPresetNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown rig preset '" + name + "' (known: " + known + ")");
}

Pose parseMount(ConfigMap m) {
  // A sensor sits on the robot: a mount 1e19 m away is a typo, not a position (docs/failure.md).
  const double x = m.getDouble("x", 0, -100, 100), y = m.getDouble("y", 0, -100, 100), z = m.getDouble("z", 0, -100, 100);
  const double roll = m.getAngle("roll", 0), pitch = m.getAngle("pitch", 0),
               yaw = m.getAngle("yaw", 0);
  m.finish();
  return Pose::fromXYZRPY(x, y, z, roll, pitch, yaw);
}

namespace {

void positive(ConfigMap& m, const std::string& key, double& field) {
  if (!m.has(key)) return;
  const ConfigValue v = m.value(key);
  const double d = v.asDouble();
  if (!(d > 0)) v.fail("must be positive");
  field = d;
}

void positiveAngle(ConfigMap& m, const std::string& key, double& field, double max_rad) {
  if (!m.has(key)) return;
  const ConfigValue v = m.value(key);
  const double a = v.asAngle();
  if (!(a > 0 && a <= max_rad)) v.fail("must be in (0, " + std::to_string(rad2deg(max_rad)) + "] deg");
  field = a;
}

void rangeAndRate(ConfigMap& m, double& range_min, double& range_max, double& rate_hz) {
  if (m.has("range_min")) {
    const ConfigValue v = m.value("range_min");
    range_min = v.asDouble();
    if (range_min < 0) v.fail("must not be negative");
  }
  positive(m, "range_max", range_max);
  positive(m, "rate_hz", rate_hz);
  if (range_min >= range_max) m.fail("range_min must be smaller than range_max");
}

// Overrides of the preset's fields; the keys depend on the kind of sensor.
void applySpecOverrides(ConfigMap m, SensorSpec& spec) {
  if (auto* p = std::get_if<PlanarScannerSpec>(&spec)) {
    positiveAngle(m, "fov", p->fov_rad, 2 * M_PI);
    positiveAngle(m, "resolution", p->resolution_rad, M_PI);
    rangeAndRate(m, p->range_min, p->range_max, p->rate_hz);
  } else if (auto* l = std::get_if<LidarSpec>(&spec)) {
    if (m.has("elevations")) {
      const ConfigValue v = m.value("elevations");
      l->elevations_rad.clear();
      for (const ConfigValue& e : v.items()) l->elevations_rad.push_back(e.asAngle());
      if (l->elevations_rad.empty()) v.fail("needs at least one layer");
    }
    positiveAngle(m, "azimuth_resolution", l->azimuth_resolution_rad, M_PI);
    rangeAndRate(m, l->range_min, l->range_max, l->rate_hz);
  } else if (auto* d = std::get_if<DepthCameraSpec>(&spec)) {
    for (auto [key, field] : {std::pair{"width", &d->width}, std::pair{"height", &d->height}}) {
      if (!m.has(key)) continue;
      const ConfigValue v = m.value(key);
      const int64_t n = v.asInt();
      if (n < 1 || n > 4096) v.fail("must be in [1, 4096] pixels");
      *field = static_cast<int>(n);
    }
    positiveAngle(m, "hfov", d->hfov_rad, deg2rad(170));
    positiveAngle(m, "vfov", d->vfov_rad, deg2rad(170));
    rangeAndRate(m, d->range_min, d->range_max, d->rate_hz);
    // A calibrated pinhole (CameraInfo's K, pixel centres on integers): all four or none, and
    // then no fields of view, which it implies.
    const char* keys[] = {"fx", "fy", "cx", "cy"};
    int given = 0;
    for (const char* k : keys) given += m.has(k);
    if (given > 0) {
      if (given < 4) m.fail("a calibrated camera needs all of fx, fy, cx, cy (pixels)");
      if (m.has("hfov") || m.has("vfov")) m.value(m.has("hfov") ? "hfov" : "vfov").fail("is implied by fx, fy, cx, cy: give one or the other");
      double k[4];
      for (int i = 0; i < 4; ++i) k[i] = m.value(keys[i]).asDouble();
      try {
        *d = depthCameraFromIntrinsics(d->width, d->height, k[0], k[1], k[2], k[3], d->range_min, d->range_max, d->rate_hz);
      } catch (const std::invalid_argument& e) {
        m.value("fx").fail(e.what());
      }
    }
  }
  m.finish();
}

bool validName(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

}  // namespace

Rig parseRig(ConfigMap m) {
  Rig rig;
  rig.name = m.getString("name", "");
  const ConfigValue list = m.value("sensors");
  std::set<std::string> names;
  for (const ConfigValue& item : list.items()) {
    ConfigMap s = item.asMap();
    const ConfigValue name = s.value("name");
    Sensor sensor;
    sensor.name = name.asString();
    if (!validName(sensor.name)) name.fail("sensor names are topic and frame names: letters, digits and '_'");
    if (!names.insert(sensor.name).second) name.fail("two sensors are named '" + sensor.name + "'");
    const ConfigValue preset = s.value("preset");
    const std::string preset_name = preset.asString();
    try {
      sensor.spec = sensorPreset(preset_name);
    } catch (const std::invalid_argument& e) {
      preset.fail(e.what());
    }
    sensor.mount = parseMount(s.map("mount"));
    if (s.has("spec")) applySpecOverrides(s.value("spec").asMap(), sensor.spec);
    s.finish();
    rig.add(std::move(sensor), preset_name);
  }
  if (rig.sensors.empty()) list.fail("a rig needs at least one sensor");
  m.finish();
  return rig;
}

Rig loadRig(const std::string& file) {
  Rig r = parseRig(ConfigMap::load(file));
  if (r.name.empty()) r.name = std::filesystem::path(file).stem().string();
  return r;
}

Rig readRig(const ConfigValue& v, const ConfigMap& context) {
  if (v.isMap()) return parseRig(v.asMap());
  const std::string s = v.asString();
  const bool is_file = s.find('/') != std::string::npos || s.ends_with(".yaml") || s.ends_with(".yml");
  if (!is_file) {
    try {
      return rigPreset(s);
    } catch (const std::invalid_argument& e) {
      v.fail(std::string(e.what()) + "; or give a rig file (*.yaml) or an inline mapping");
    }
  }
  const std::string path = context.resolvePath(s);
  if (!std::filesystem::exists(path)) v.fail("rig file '" + path + "' does not exist");
  return loadRig(path);
}

}  // namespace polyloc
