// The `tracking:` config section: defaults, values, errors that name the key, sensor names
// checked against the rig; the PeopleTracker's choice of scanners.
#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/tracking/config_yaml.hpp>
#include <polyloc/tracking/people_tracker.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_config {

using namespace polyloc;


std::string errorOf(const std::string& text, const Rig* rig = nullptr) {
  try {
    ConfigMap m = ConfigMap::parse(text, "t.yaml");
    parseTrackingConfig(m.map("tracking"), rig);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}


TEST(TrackingConfigYaml, ReadsValuesAndKeepsDefaults) {
  ConfigMap m = ConfigMap::parse("tracking:\n  sensors: [a, b]\n  sync_tolerance: 0.01\n"
                                 "  motion: {margin: 0.2, reference_ages: [0.1, 0.5]}\n"
                                 "  cluster: {min_points: 5}\n  tracker: {confirm_hits: 4, timeout: 2}\n",
                                 "t.yaml");
  const TrackingConfig c = parseTrackingConfig(m.map("tracking"));
  EXPECT_EQ(c.sensors, (std::vector<std::string>{"a", "b"}));
  EXPECT_DOUBLE_EQ(c.sync_tolerance, 0.01);
  EXPECT_DOUBLE_EQ(c.motion.margin, 0.2);
  EXPECT_EQ(c.motion.reference_ages, (std::vector<double>{0.1, 0.5}));
  EXPECT_DOUBLE_EQ(c.motion.max_range, MotionConfig{}.max_range);
  EXPECT_EQ(c.cluster.min_points, 5u);
  EXPECT_DOUBLE_EQ(c.cluster.distance, ClusterConfig{}.distance);
  EXPECT_EQ(c.tracker.confirm_hits, 4);
  EXPECT_DOUBLE_EQ(c.tracker.timeout, 2.0);
  EXPECT_DOUBLE_EQ(c.tracker.gate, TrackerConfig{}.gate);
}

TEST(TrackingConfigYaml, UnknownKeysAndBadValuesNameTheKey) {
  EXPECT_NE(errorOf("tracking:\n  motion: {margn: 0.1}\n").find("margn"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  motion: {margn: 0.1}\n").find("t.yaml"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  trackr: {}\n").find("trackr"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  tracker: {confirm_hits: 0}\n").find("confirm_hits"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  motion: {reference_ages: []}\n").find("reference_ages"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  motion: {min_range: 5, max_range: 4}\n").find("max_range"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  cluster: {distance: -1}\n").find("distance"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  sensors: s300\n").find("sensors"), std::string::npos);
}

TEST(TrackingConfigYaml, SensorNamesAreCheckedAgainstTheRig) {
  const Rig lisa = rigPreset("lisa");
  EXPECT_EQ(errorOf("tracking:\n  sensors: [s300_front_left]\n", &lisa), "");
  const std::string missing = errorOf("tracking:\n  sensors: [s300_front]\n", &lisa);
  EXPECT_NE(missing.find("s300_front"), std::string::npos);
  EXPECT_NE(missing.find("t.yaml:2"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  sensors: [urg_front]\n", &lisa).find("tilted"), std::string::npos);
  EXPECT_NE(errorOf("tracking:\n  sensors: [tof_front]\n", &lisa).find("not a planar scanner"), std::string::npos);
}

TEST(TrackingConfigYaml, LabConfigHasATrackingSection) {
  const PolylocConfig c = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  EXPECT_EQ(c.tracking.sensors, (std::vector<std::string>{"s300_front_left", "s300_rear_right"}));
  EXPECT_EQ(trackingSensors(c.rig, c.tracking), (std::vector<size_t>{0, 1}));
}

TEST(TrackingConfigYaml, PeopleTrackerUsesTheLevelScanners) {
  const Rig lisa = rigPreset("lisa");
  PeopleTracker people(lisa, TrackingConfig{});
  EXPECT_EQ(people.sensors(), (std::vector<size_t>{0, 1}));  // the two S300, not the tilted URGs
  const std::vector<float> urg(lisa.sensors[2].beams().size(), 1.f);
  EXPECT_EQ(people.addScan(2, 0, Pose(), urg), ScanCheck::Ok);  // not a tracking sensor: ignored
  EXPECT_EQ(people.addScan(99, 0, Pose(), urg), ScanCheck::Ok);
  EXPECT_EQ(people.counters().ignored, 2u);
  EXPECT_EQ(people.addScan(0, 0, Pose(), urg), ScanCheck::WrongSize);
  EXPECT_EQ(people.counters().rejected, 1u);
  TrackingConfig c;
  c.sensors = {"urg_front"};
  EXPECT_THROW(PeopleTracker(lisa, c), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(rigPreset("taser"), c), std::invalid_argument);  // no such sensor
}

}  // namespace polyloc::t_tracking_config
