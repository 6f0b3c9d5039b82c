// Whole simulated runs: the bundled scenarios drive where the robot fits, the output is the
// same bytes for the same seed (on any thread count) and different for another seed, topics,
// rates and frames are as documented, ramps tilt the robot, chairs move.
#include "sim_fixtures.hpp"

#include <polyloc/mapgen/generate.hpp>
#include <polyloc/sim/chairs.hpp>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <set>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_run {

using namespace polyloc;


const std::string kSource = POLYLOC_SOURCE_DIR;

Scenario bundled(const std::string& name, double duration = 0) {
  Scenario s = loadScenario(kSource + "/maps/scenarios/" + name + ".yaml");
  if (duration > 0) s.duration = duration;
  return s;
}

std::string runDump(const Scenario& s, const Mesh& map) {
  Simulator sim(s, map);
  test::CaptureWriter w;
  sim.run(w);
  return test::dumpAll(w);
}


// Every 5 cm of every route, and at every stop in all headings, the robot's outline is free of
// walls and furniture (moved chairs included) at body heights (the floor excluded).
TEST(SimRun, BundledRoutesAreCollisionFree) {
  for (const char* name : {"lab_tour", "office_patrol", "office_loop", "ramp_6dof", "crowd"}) {
    const Scenario s = bundled(name);
    Simulator sim(s, loadScenarioMap(s));
    const RobotSpec& robot = s.config.robot;
    const std::vector<Eigen::Vector2d> outline = robot.outline(0.05);
    std::vector<PlanarState> poses = sim.trajectory().sample(0.05);
    for (size_t l = 0; l < sim.trajectory().numLegs(); ++l) {  // turns in place at the stops
      const SplinePath& leg = sim.trajectory().leg(l);
      for (double s_at : {0.0, leg.length()})
        for (int k = 0; k < 36; ++k) {
          PlanarState st;
          st.x = leg.position(s_at).x(), st.y = leg.position(s_at).y(), st.yaw = k * M_PI / 18;
          poses.push_back(st);
        }
    }
    std::vector<Pose> base(poses.size());
    sim.floor().poses(poses, base.data());
    std::vector<Eigen::Vector3f> points;
    for (const Pose& p : base)
      for (double h : {0.15, 0.5, 0.9, robot.height - 0.05})
        for (const auto& q : outline) points.push_back((p * Eigen::Vector3d(q.x(), q.y(), h)).cast<float>());
    std::vector<uint8_t> free(points.size());
    sim.caster().queryFree(points, 0.02f, free.data());
    size_t blocked = 0;
    for (size_t i = 0; i < points.size(); ++i)
      if (!free[i] && blocked++ < 5)
        ADD_FAILURE() << name << ": robot outline hits the map at (" << points[i].x() << ", " << points[i].y()
                      << ", " << points[i].z() << ")";
    EXPECT_EQ(blocked, 0u) << name << ": " << points.size() << " points checked";
    EXPECT_EQ(sim.floor().misses(), 0u) << name;
  }
}

// People walk past and around the robot, never into it (their bodies reach 0.3 m from their
// centre line with the arms swinging).
TEST(SimRun, BundledPeopleKeepClearOfTheRobot) {
  for (const char* name : {"lab_tour", "office_patrol", "office_loop", "ramp_6dof", "crowd"}) {
    const Scenario s = bundled(name);
    Simulator sim(s, loadScenarioMap(s));
    const double reach = s.config.robot.boundingRadius() + 0.3;
    double closest = 1e9;
    for (double t = 0; t <= sim.duration(); t += 0.02) {
      const PlanarState r = sim.trajectory().at(t);
      for (size_t i = 0; i < sim.people().size(); ++i) {
        const PersonState p = sim.people().state(i, t, {r.x, r.y});
        if (p.present) closest = std::min(closest, std::hypot(p.x - r.x, p.y - r.y));
      }
    }
    EXPECT_GT(closest, reach) << name;
  }
}

// The crowd walks round loops in lanes: nobody walks through anybody (bodies about 0.5 m wide).
TEST(SimRun, CrowdPeopleKeepApart) {
  const Scenario s = bundled("crowd");
  Simulator sim(s, loadScenarioMap(s));
  double closest = 1e9;
  for (double t = 0; t <= sim.duration(); t += 0.02) {
    const PlanarState r = sim.trajectory().at(t);
    for (size_t i = 0; i < sim.people().size(); ++i)
      for (size_t j = i + 1; j < sim.people().size(); ++j) {
        const PersonState a = sim.people().state(i, t, {r.x, r.y}), b = sim.people().state(j, t, {r.x, r.y});
        if (a.present && b.present) closest = std::min(closest, std::hypot(a.x - b.x, a.y - b.y));
      }
  }
  EXPECT_GT(closest, 0.6);
  EXPECT_EQ(sim.people().size(), 8u);
}

TEST(SimRun, SameSeedSameBytesDifferentSeedDifferent) {
  Scenario s = bundled("lab_tour", 2.0);
  const Mesh map = loadScenarioMap(s);
  const std::string a = runDump(s, map);
  const std::string b = runDump(s, map);
  EXPECT_EQ(a, b);
  std::string one_thread;
  tbb::task_arena(1).execute([&] { one_thread = runDump(s, map); });
  EXPECT_EQ(a, one_thread);
  s.seed = 2;
  EXPECT_NE(a, runDump(s, map));
}

TEST(SimRun, TopicsRatesAndFrames) {
  const Scenario s = bundled("lab_tour", 3.0);
  Simulator sim(s, loadScenarioMap(s));
  test::CaptureWriter w;
  const SimSummary sum = sim.run(w);
  EXPECT_EQ(sum.messages, w.entries.size());
  // Stamps never go back; everything within [start, start + 3 s].
  int64_t last = 0;
  for (const auto& e : w.entries) {
    ASSERT_GE(e.stamp, last);
    ASSERT_LE(e.stamp, s.start_time_ns + 3000000000LL);
    last = e.stamp;
  }
  EXPECT_EQ(w.entries.front().topic, "/tf_static");
  EXPECT_EQ(w.on("/odom").size(), 151u);          // 50 Hz, t = 0 .. 3 s
  EXPECT_EQ(w.on("/ground_truth").size(), 151u);
  EXPECT_EQ(w.on("/tf").size(), 151u);
  EXPECT_EQ(w.on("/scan/s300_front_left").size(), 38u);  // 12.5 Hz
  EXPECT_EQ(w.on("/scan/urg_left").size(), 31u);         // 10 Hz
  EXPECT_EQ(w.on("/depth/tof_front/image").size(), 61u); // 20 Hz
  EXPECT_EQ(w.on("/depth/tof_front/amplitude").size(), 61u);
  EXPECT_EQ(w.on("/depth/tof_front/camera_info").size(), 61u);
  EXPECT_EQ(w.on("/depth/tof_front/artefacts").size(), 61u);
  EXPECT_EQ(w.on("/ground_truth/people").size(), 2 * 38u);  // per frame of either S300
  EXPECT_EQ(w.on("/ground_truth/vrs").size(), 8u);          // every 5th frame of the first S300
  EXPECT_EQ(sum.topics.size(), 16u);
  // The people truth (present people, the beams of the frame on them; none yet at 3 s), the true
  // VRS in base_link, the ToF artefact tags.
  const auto people = std::get<msg::TrackArray>(w.on("/ground_truth/people").back()->message);
  EXPECT_EQ(people.header.frame_id, "map");
  const auto vrs = std::get<msg::LaserScan>(w.on("/ground_truth/vrs").front()->message);
  EXPECT_EQ(vrs.header.frame_id, "base_link");
  EXPECT_EQ(vrs.ranges.size(), 720u);
  const auto art = std::get<msg::Image>(w.on("/depth/tof_front/artefacts").front()->message);
  EXPECT_EQ(art.encoding, "mono8");
  EXPECT_EQ(art.data.size(), 64u * 50u);
  const auto tf_static = std::get<msg::TFMessage>(w.entries.front().message);
  EXPECT_EQ(tf_static.transforms.size(), 8u);  // 7 mounts and the ToF optical frame
  // Odometry starts at identity in the odom frame; ground truth at the first waypoint in map.
  const auto odom = std::get<msg::Odometry>(w.on("/odom").front()->message);
  EXPECT_EQ(odom.header.frame_id, "odom");
  EXPECT_EQ(odom.child_frame_id, "base_link");
  EXPECT_EQ(odom.pose.pose.position.x, 0.0);
  const auto gt = std::get<msg::PoseStamped>(w.on("/ground_truth").front()->message);
  EXPECT_EQ(gt.header.frame_id, "map");
  EXPECT_NEAR(gt.pose.position.x, 1.3, 1e-9);
  EXPECT_NEAR(gt.pose.position.y, 1.75, 1e-9);
  EXPECT_EQ(msg::toNs(gt.header.stamp), s.start_time_ns);
  const auto tf = std::get<msg::TFMessage>(w.on("/tf").back()->message);
  EXPECT_EQ(tf.transforms[0].header.frame_id, "odom");
  EXPECT_EQ(tf.transforms[0].child_frame_id, "base_link");
  // The odometry is close to the truth after a short drive (drift is small).
  const auto last_odom = std::get<msg::Odometry>(w.on("/odom").back()->message);
  const auto last_gt = std::get<msg::PoseStamped>(w.on("/ground_truth").back()->message);
  EXPECT_NEAR(last_odom.pose.pose.position.x, last_gt.pose.position.x - 1.3, 0.05);
}

TEST(SimRun, RampTiltsTheRobot) {
  Scenario s = bundled("ramp_6dof");
  s.floor.unevenness = 0;
  Simulator sim(s, loadScenarioMap(s));
  // Half way up the ramp (y = 8 m, facing north): 0.15 m up, nose up by atan(0.06).
  bool checked = false;
  for (double t = 0; t < sim.duration(); t += 0.1) {
    const PlanarState st = sim.trajectory().at(t);
    if (std::abs(st.y - 8.0) < 0.05 && std::abs(angleDiff(st.yaw, M_PI / 2)) < 0.01) {
      const Pose p = sim.groundTruth(t);
      EXPECT_NEAR(p.z(), 0.15, 0.005);
      EXPECT_NEAR(p.pitch(), -std::atan(0.06), 1e-3);
      EXPECT_NEAR(p.roll(), 0.0, 1e-3);
      checked = true;
      break;
    }
  }
  EXPECT_TRUE(checked);
  // On the platform: 0.3 m, level.
  PlanarState on_top;
  on_top.x = 23.6, on_top.y = 12.0, on_top.yaw = 0.3;
  const Pose top = sim.floor().pose(on_top);
  EXPECT_NEAR(top.z(), 0.3, 1e-4);
  EXPECT_NEAR(top.pitch(), 0.0, 1e-6);
  // With unevenness the robot rocks a little (well under a degree).
  s.floor.unevenness = 0.003;
  Simulator bumpy(s, loadScenarioMap(s));
  double max_tilt = 0, sum_tilt = 0;
  int n = 0;
  for (double t = 0; t < 10; t += 0.1, ++n) {
    const Pose p = bumpy.groundTruth(t);
    max_tilt = std::max({max_tilt, std::abs(p.roll()), std::abs(p.pitch())});
    sum_tilt += std::abs(p.roll());
  }
  EXPECT_GT(sum_tilt / n, deg2rad(0.05));
  EXPECT_LT(max_tilt, deg2rad(2.0));
}

TEST(SimRun, ChairsMoveBetweenRuns) {
  MapLayout layout;
  const Mesh lab = generateMap("lab", &layout);
  const auto chairs = findObjects(lab, "chair");
  ASSERT_EQ(chairs.size(), layout.chairs.size());
  for (const auto& c : chairs) {  // each found object is one chair of the layout
    double best = 1e9;
    for (const auto& l : layout.chairs) best = std::min(best, (c.centre() - l.cast<double>()).norm());
    EXPECT_LT(best, 0.2);
  }
  ChairMoves moves;
  ChairMove move;
  move.from = layout.chairs[0].cast<double>(), move.to = move.from + Eigen::Vector2d(0.5, 0), move.where = "here";
  moves.moves.push_back(move);
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> moved;
  const Mesh m = moveChairs(lab, moves, 1, &moved);
  ASSERT_EQ(moved.size(), 1u);
  EXPECT_NEAR((moved[0].second - moved[0].first).norm(), 0.5, 0.2);
  EXPECT_EQ(findObjects(m, "chair").size(), chairs.size());
  moves.moves[0].from = {-50, -50};
  try {
    moveChairs(lab, moves, 1);
    ADD_FAILURE() << "no error for a move without a chair";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("here: no 'chair'"), std::string::npos) << e.what();
  }
  // Seed-driven: every chair moves, differently for another seed, within the limits.
  ChairMoves random;
  random.random_shift = 0.3, random.random_rotation = deg2rad(20);
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> a, b;
  moveChairs(lab, random, 1, &a);
  moveChairs(lab, random, 2, &b);
  ASSERT_EQ(a.size(), chairs.size());
  bool differ = false;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_LE((a[i].second - a[i].first).norm(), 0.3 + 1e-9);
    differ |= (a[i].second - b[i].second).norm() > 1e-6;
  }
  EXPECT_TRUE(differ);
}

}  // namespace polyloc::t_sim_run
