// The VRS on simulated drives of the lisa rig (thesis 6.2): chair seats above the scan plane,
// a person circling the robot, a table edge approached, a danger zone, low bins seen by the ToF
// camera only. Frames at the ground-truth pose (what localisation gives).
#include "vrs_fixtures.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/sim/vrs_truth.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_vrs_scenarios {

using namespace polyloc;
using namespace polyloc::test;


VrsConfig horizontalOnly() {
  VrsConfig c;
  c.memory.enabled = false;
  for (const char* s : {"urg_front", "urg_left", "urg_rear", "urg_right", "tof_front"}) c.sources.push_back({s, VrsMode::Off});
  return c;
}

// Distance along the robot's heading from its front... from base_link to the plane x = edge.
double ahead(const Pose& truth, double edge_x) { return edge_x - truth.x(); }


// Thesis fig. 6.15-6.17: a chair in the corridor; its seat is above the horizontal scan plane.
TEST(VrsScenario, ChairSeatAboveTheScanPlane) {
  VrsDrive d;
  d.map = roomMesh(0, -1.2f, 12, 1.2f);
  addStool(d.map, 5.0f, 0.0f);  // seat front edge at x = 4.77
  const double edge = 4.77;
  d.from = {1.0, 0.0}, d.to = {edge - 0.8, 0.0};
  d.wait = 5.0;
  const Rig lisa = rigPreset("lisa");
  RobotSpec robot = vrsScenario(d).config.robot;
  VirtualRangeScanner full(lisa, robot, d.config), flat(lisa, robot, horizontalOnly());
  double last_err = 1e9, last_flat = 0, worst_standing = 0, t_end = 0, stop_t = 0;
  size_t standing = 0;
  // Both scanners side by side on the same frames.
  runVrs(d, {&full, &flat}, [&](const VrsStep& s) {
    stop_t = s.sim.duration() - d.wait;
    const double truth = ahead(s.truth, edge);
    last_err = std::abs(vrsAt(s.scans[0], 0) - truth), last_flat = vrsAt(s.scans[1], 0) - truth, t_end = s.t;
    if (s.t > stop_t + 0.5) worst_standing = std::max(worst_standing, last_err), ++standing;
  });
  std::printf("[vrs] chair: full VRS error %.3f m (worst while standing %.3f m over %zu updates), flat VRS %.2f m behind the seat\n",
              last_err, worst_standing, standing, last_flat);
  EXPECT_GT(standing, 40u);
  EXPECT_LT(worst_standing, 0.05);  // the seat at the right distance, from memory
  EXPECT_GT(last_flat, 0.3);         // the horizontal scanners look through the legs
  EXPECT_GT(t_end, stop_t);
}

// A person circling the robot: tracked, so none of their points enter the memory.
TEST(VrsScenario, CirclingPersonLeavesNoMemory) {
  VrsDrive d;
  d.map = roomMesh(-6, -6, 6, 6);
  d.from = {0.0, 0.0}, d.to = {0.3, 0.0};
  d.speed = 0.1, d.wait = 12.0;
  PersonSpec p;
  p.name = "circler";
  p.circle = true, p.around_robot = true, p.radius = 1.3, p.speed = 1.0;
  d.people = {p};
  const Rig lisa = rigPreset("lisa");
  const RobotSpec robot = vrsScenario(d).config.robot;
  auto near_person = [](const VirtualRangeScanner& v) {
    size_t n = 0;
    for (const auto& q : v.memory().points()) {
      const double r = q.cast<double>().norm();
      n += r > 0.7 && r < 1.9;  // the ring the person walks on (the robot is near the origin)
    }
    return n;
  };
  VirtualRangeScanner untracked(lisa, robot, d.config);
  runVrs(d, untracked, [](const VrsStep&) {});
  d.moving = truePeople;
  VirtualRangeScanner tracked(lisa, robot, d.config);
  runVrs(d, tracked, [](const VrsStep&) {});
  // The same with the people tracker's confirmed tracks instead of the truth.
  d.moving = nullptr;
  d.track_people = true;
  d.tracking = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml").tracking;
  VirtualRangeScanner by_tracker(lisa, robot, d.config);
  runVrs(d, by_tracker, [](const VrsStep&) {});
  std::printf("[vrs] circling person: memory cells on the ring %zu untracked, %zu with true tracks, %zu with tracking/ (%lu points kept out)\n",
              near_person(untracked), near_person(tracked), near_person(by_tracker), (unsigned long)by_tracker.counters().memory_moving);
  EXPECT_GT(near_person(untracked), 10u);  // without the tracks filter the person would be remembered
  EXPECT_EQ(near_person(tracked), 0u);
  EXPECT_EQ(near_person(by_tracker), 0u);
}

// The remembered table edge stays in place while the robot approaches and stands in front.
TEST(VrsScenario, TableEdgeStaysWhileApproachingAndStopped) {
  VrsDrive d;
  d.map = roomMesh(0, -3, 8, 3);
  mapgen::MeshBuilder b(d.map);
  b.box({5.0f, -0.8f, 0.715f}, {5.8f, 0.8f, 0.75f}, "table");
  for (float x : {5.05f, 5.71f})
    for (float y : {-0.75f, 0.71f}) b.box({x, y, 0.f}, {x + 0.04f, y + 0.04f, 0.715f}, "table");
  const double edge = 5.0;
  d.from = {1.0, 0.0}, d.to = {edge - 0.6, 0.0};
  d.wait = 15.0;
  const Rig lisa = rigPreset("lisa");
  VirtualRangeScanner vrs(lisa, vrsScenario(d).config.robot, d.config);
  double worst = 0, sum2 = 0;
  size_t checked = 0, segments = 0;
  runVrs(d, vrs, [&](const VrsStep& s) {
    // Every segment against the true VRS of the scene (walls, legs, top) within 1.2 m, where
    // lisa's tilted URGs have looked (their lines reach the floor 1.2-1.5 m out).
    const std::vector<float> t = trueVirtualScan(s.sim.caster(), PeopleScene{}, s.truth, vrs.config());
    const VrsError e = compareVirtualScan(s.scan.ranges, s.scan.source, t, s.scan.range_max, 1.2);
    if (s.t > 0.5) sum2 += e.rmse_m * e.rmse_m * double(e.segments), segments += e.segments;  // once every sensor spoke
    const double truth = ahead(s.truth, edge);
    if (truth > 1.0) return;  // from here on the edge has been seen (URGs reach 0.6 m ahead at 0.75 m)
    worst = std::max(worst, std::abs(double(vrsAt(s.scan, 0)) - truth));
    ++checked;
  });
  const double rmse = std::sqrt(sum2 / double(std::max<size_t>(segments, 1)));
  std::printf("[vrs] table edge: worst error %.3f m over %zu updates (approach and 15 s standing); all segments within 1.2 m: RMSE %.3f m over %zu\n",
              worst, checked, rmse, segments);
  EXPECT_LT(rmse, 0.05);
  EXPECT_GT(checked, 150u);
  EXPECT_LT(worst, 0.05);
}

// The lab's stairwell (label "danger") is in every VRS that looks at it.
TEST(VrsScenario, DangerZoneIsAlwaysInTheVrs) {
  VrsDrive d;
  d.map = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  d.from = {21.5, 2.0}, d.to = {21.5, 6.0};  // the loading hall, past the stairwell (x 23.9-25.6, y 4.0-8.68)
  d.wait = 1.0;
  const Rig lisa = rigPreset("lisa");
  VirtualRangeScanner vrs(lisa, vrsScenario(d).config.robot, d.config, &d.map);
  // Exact distance along a ray to the stairwell's hole (the railing stands 5 cm outside it).
  const Eigen::Vector2d lo(23.9, 4.0), hi(25.6, 8.68);
  auto hole = [&](const Eigen::Vector2d& o, double a, double grow) {
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    double t0 = 0, t1 = 1e9;
    for (int k = 0; k < 2; ++k) {
      if (std::abs(dir[k]) < 1e-12) {
        if (o[k] < lo[k] - grow || o[k] > hi[k] + grow) return 1e9;
        continue;
      }
      double ta = (lo[k] - grow - o[k]) / dir[k], tb = (hi[k] + grow - o[k]) / dir[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    return t0 <= t1 ? t0 : 1e9;
  };
  size_t segments = 0, missing = 0, by_zone = 0;
  runVrs(d, vrs, [&](const VrsStep& s) {
    const Eigen::Vector2d o = s.truth.translation().head<2>();
    for (size_t i = 0; i < s.scan.size(); ++i) {
      const double a = s.truth.yaw() + s.scan.angleOf(i);
      const double dh = hole(o, a, 0.0);
      if (dh > s.scan.range_max - 0.2) continue;
      ++segments;
      const double r = s.scan.ranges[i];
      if (!(r <= dh + 0.01)) ++missing;  // farther than the hole's edge: the zone is missing
      by_zone += (s.scan.source[i] & kVrsDanger) != 0;
    }
  });
  std::printf("[vrs] danger zone: %zu segments looked at the stairwell, %zu missed it, %zu got their range from it\n",
              segments, missing, by_zone);
  EXPECT_GT(segments, 1000u);
  EXPECT_EQ(missing, 0u);
  EXPECT_GT(by_zone, segments / 2);  // mostly nothing real is nearer: the zone makes the range
}

// A low box below the S300s' scan plane (0.10 m): only the ToF camera sees it, and only from
// farther than 1.6 m; the memory keeps it when the robot is closer.
TEST(VrsScenario, LowBinSeenByTofStays) {
  VrsDrive d;
  d.map = roomMesh(0, -3, 8, 3);
  mapgen::MeshBuilder b(d.map);
  b.box({5.0f, -0.2f, 0.f}, {5.3f, 0.2f, 0.09f}, "bin");
  const double edge = 5.0;
  d.from = {1.0, 0.0}, d.to = {edge - 0.7, 0.0};
  d.wait = 5.0;
  const Rig lisa = rigPreset("lisa");
  VirtualRangeScanner vrs(lisa, vrsScenario(d).config.robot, d.config);
  double last = 0, truth = 0;
  runVrs(d, vrs, [&](const VrsStep& s) { last = vrsAt(s.scan, 0), truth = ahead(s.truth, edge); });
  std::printf("[vrs] low bin: VRS %.3f m, truth %.3f m\n", last, truth);
  EXPECT_NEAR(last, truth, 0.05);
}

}  // namespace polyloc::t_vrs_scenarios
