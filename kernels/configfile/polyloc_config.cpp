#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/depth/config_yaml.hpp>
#include <polyloc/mcl/config_yaml.hpp>
#include <polyloc/vrs/config_yaml.hpp>
#include <polyloc/tracking/config_yaml.hpp>

#include <algorithm>
#include <filesystem>

namespace polyloc {

MapConfig readMapConfig(const ConfigValue& v, const ConfigMap& context) {
  MapConfig mc;
  ConfigValue file_value = v;
  if (v.isMap()) {
    ConfigMap m = v.asMap();
    file_value = m.value("file");
    mc.load.scale = m.getDouble("scale", 1.0, 1e-9, 1e9);
    if (m.has("up_axis")) {
      const ConfigValue u = m.value("up_axis");
      try {
        mc.load.up_axis = parseUpAxis(u.asString());
      } catch (const MapError& e) {
        u.fail(e.what());
      }
    }
    mc.load.merge_vertices = m.getBool("merge_vertices", true);
    m.finish();
  }
  mc.file = context.resolvePath(file_value.asString());
  if (!std::filesystem::is_regular_file(mc.file))
    file_value.fail("map file '" + mc.file + "' does not exist");
  return mc;
}

double particleClearance(const RobotSpec& robot, const MclConfig& mcl) {
  return std::max(0.0, robot.inscribedRadius() - mcl.clearance_margin);
}

void applyRobot(PolylocConfig& c, const RobotSpec& robot) {
  if (c.vrs.robot_height == c.robot.height) c.vrs.robot_height = robot.height;
  c.robot = robot;
  c.mcl.motion.omni = robot.kinematics == Kinematics::Omni;
  c.mcl.clearance = particleClearance(c.robot, c.mcl);
}

PolylocConfig loadConfig(const std::string& path, const ConfigLoad& load) {
  ConfigMap m = ConfigMap::load(path);
  PolylocConfig c;
  c.file = path;
  if (m.has("map") || !load.map_optional) c.map = readMapConfig(m.value("map"), m);
  applyRobot(c, parseRobot(m.map("robot")));
  c.vrs.robot_height = c.robot.height;
  const bool recorded = !m.has("rig") || (m.value("rig").isScalar() && m.value("rig").asString() == "recorded");
  if (recorded && !load.recorded_rig) {
    if (!m.has("rig")) m.value("rig");  // the usual "missing key" error
    m.value("rig").fail("a recorded rig takes its scanners from a recording (polyloc localize, relocalize, "
                        "eval carmen); this command needs the rig's sensors: a preset, a rig file or a mapping");
  }
  if (recorded) c.rig_from_recording = true;
  else c.rig = readRig(m.value("rig"), m);
  const Rig* rig = recorded ? nullptr : &c.rig;  // sensor names are checked when the rig is known
  if (m.has("mcl")) {
    // mcl.motion.drive defaults to robot.kinematics; stated again it must say the same.
    c.mcl = parseMclConfig(m.map("mcl"), rig, c.mcl);
    if (c.mcl.motion.omni != (c.robot.kinematics == Kinematics::Omni))
      m.map("mcl").map("motion").value("drive").fail(std::string("says ") + (c.mcl.motion.omni ? "omni" : "differential") +
                                                     " but robot.kinematics is " + kinematicsName(c.robot.kinematics) +
                                                     ": give it once, in robot.kinematics");
    c.mcl.clearance = particleClearance(c.robot, c.mcl);
  }
  if (m.has("vrs")) c.vrs = parseVrsConfig(m.map("vrs"), c.robot.height);
  if (m.has("tracking")) c.tracking = parseTrackingConfig(m.map("tracking"), rig);
  if (m.has("depth_filter")) c.depth_filter = parseDepthFilterConfig(m.map("depth_filter"));
  m.allow("polylocd");  // the daemon's own section (service/pipeline/daemon_config.hpp)
  m.finish();
  return c;
}

DepthFilterConfig loadDepthFilterConfig(const std::string& file) {
  ConfigMap m = ConfigMap::load(file);
  if (m.has("map")) return loadConfig(file).depth_filter;
  DepthFilterConfig c;
  if (m.has("depth_filter")) c = parseDepthFilterConfig(m.map("depth_filter"));
  m.finish();
  return c;
}

}  // namespace polyloc
