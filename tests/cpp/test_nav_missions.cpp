// What `polyloc eval nav` scores of a mission (engines/nav_missions.hpp), from the commands a
// controller writes and the simulated truth.
#include "engines/nav_missions.hpp"

#include <polyloc_shm.h>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_nav_missions {

using namespace polyloc;
using namespace polyloc::engines;


struct Missions {
  polynav::Zones zones;
  MissionTracker tracker;
  explicit Missions(std::vector<polynav::GoalSpot> goals)
      : tracker(zones, std::move(goals), {{0.3, 0.25}, {-0.3, 0.25}, {-0.3, -0.25}, {0.3, -0.25}},
                [](const Eigen::Vector2d&, const polynav::GoalSpot&) { return 1.0; }) {}
};


// Was: the goal error was taken where the robot stood when the controller said "reached", while
// the base was still braking; the mission's result was final before the robot was.
TEST(MissionTracker, AMissionIsScoredWhereTheRobotComesToRest) {
  Missions r({{"bench", {2.0, 0.0, 0.0}, 0.5}});
  MissionTracker& t = r.tracker;
  t.onCommand(0, POLYLOC_NAV_DRIVING, "driving", 0.0, Pose::planar(0, 0, 0));
  t.onStep(Pose::planar(1.0, 0, 0), 0.5, 0.0, 0.2);
  t.onCommand(0, POLYLOC_NAV_REACHED, "reached", 4.0, Pose::planar(2.0, 0, 0));  // at the goal, still at speed
  EXPECT_FALSE(t.results()[0].ended);
  EXPECT_TRUE(t.settling());
  EXPECT_FALSE(t.done());
  t.onStep(Pose::planar(2.03, 0, 0), 0.2, 0.0, 0.2);   // braking
  EXPECT_FALSE(t.results()[0].ended);
  t.onStep(Pose::planar(2.04, 0, 0.01), 0.0, 0.05, 0.2);  // stopped driving, still turning
  EXPECT_FALSE(t.results()[0].ended);
  t.onStep(Pose::planar(2.04, 0, 0.01), 0.0, 0.0, 0.2);   // at rest
  const MissionResult& m = t.results()[0];
  ASSERT_TRUE(m.ended);
  EXPECT_TRUE(m.reached);
  EXPECT_TRUE(t.done());
  EXPECT_NEAR(m.goal_error_m, 0.04, 1e-9);
  EXPECT_NEAR(m.goal_yaw_error_deg, 0.01 * 180 / M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(m.t_end, 4.0);  // the mission's time is the controller's verdict
  EXPECT_NEAR(m.driven_m, 1.04, 1e-9);
}

TEST(MissionTracker, TheNextMissionOrAnAbortEndsTheBrakingOne) {
  Missions r({{"a", {1.0, 0.0, 0.0}, 0.5}, {"b", {0.0, 0.0, 0.0}, 0.5}});
  MissionTracker& t = r.tracker;
  t.onCommand(0, POLYLOC_NAV_DRIVING, "", 0.0, Pose::planar(0, 0, 0));
  t.onStep(Pose::planar(0.98, 0, 0), 0.3, 0.0, 0.2);
  t.onCommand(0, POLYLOC_NAV_REACHED, "reached", 3.0, Pose::planar(0.98, 0, 0));
  t.onCommand(1, POLYLOC_NAV_DRIVING, "", 3.1, Pose::planar(1.01, 0, 0));  // moved on while braking
  EXPECT_TRUE(t.results()[0].ended);
  EXPECT_TRUE(t.results()[0].reached);  // its verdict stands: not "moved on without ending it"
  EXPECT_NEAR(t.results()[0].goal_error_m, 0.01, 1e-9);
  t.onCommand(1, POLYLOC_NAV_FAILED, "blocked", 9.0, Pose::planar(0.5, 0, 0));
  t.onStep(Pose::planar(0.45, 0, 0), 0.1, 0.0, 0.2);
  t.abort(9.5, "polynav ended");  // gone before the base stood: scored where it was last seen
  const MissionResult& b = t.results()[1];
  EXPECT_TRUE(b.ended);
  EXPECT_FALSE(b.reached);
  EXPECT_EQ(b.end_status, "blocked");
  EXPECT_NEAR(b.goal_error_m, 0.45, 1e-9);
}

}  // namespace polyloc::t_nav_missions
