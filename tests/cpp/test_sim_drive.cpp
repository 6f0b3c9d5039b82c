// The closed-loop simulator (sim/drive.hpp): the stepper gives the same messages as a whole run
// along the same poses, the robot goes where its commands take it (known distances), a wall
// stops it and is named, the command timeout stops it, a person walking into a standing robot
// is not the robot's collision, bad options are refused.
#include "sim_fixtures.hpp"

#include <polyloc/sim/drive.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_drive {

using namespace polyloc;


const std::string kSource = POLYLOC_SOURCE_DIR;

Scenario navScenario(bool people) {
  Scenario s = loadScenario(kSource + "/maps/scenarios/lab_nav.yaml");
  if (!people) s.people.clear();
  return s;
}

// Commands every 0.1 s (the base's watchdog wants one every 0.5 s) for `seconds`.
void drive(DriveSim& d, double vx, double wz, double seconds, test::CaptureWriter* out = nullptr) {
  test::CaptureWriter sink;
  const double end = d.nowS() + seconds;
  double next = d.nowS();
  while (d.nowS() < end) {
    if (d.nowS() >= next) {
      d.command({std::llround(d.nowS() * 1e9), vx, 0, wz});
      next += 0.1;
    }
    d.step(out ? *out : sink);
  }
}


TEST(SimDrive, StepperGivesTheMessagesOfAWholeRun) {
  Scenario s = loadScenario(kSource + "/maps/scenarios/lab_tour.yaml");
  s.duration = 2.0;
  const Mesh map = loadScenarioMap(s);
  test::CaptureWriter whole, stepped;
  {
    Simulator sim(s, map);
    sim.run(whole);
  }
  Simulator sim(s, map);
  SimStepper stepper(sim);
  while (stepper.nextEventNs() <= std::llround(2.0 * 1e9))
    stepper.emit(sim.trajectory().at(double(stepper.nextEventNs()) * 1e-9), stepped);
  ASSERT_GT(whole.entries.size(), 100u);
  EXPECT_EQ(test::dumpAll(whole), test::dumpAll(stepped));
}

TEST(SimDrive, GoesWhereTheCommandsTakeIt) {
  Scenario s = navScenario(false);
  Simulator sim(s, loadScenarioMap(s));
  DriveOptions o;
  o.command_latency = 0.05;
  DriveSim d(sim, o);
  EXPECT_NEAR(d.truth().x(), 2.0, 1e-9);
  EXPECT_NEAR(d.truth().y(), 1.75, 1e-9);
  test::CaptureWriter out;
  drive(d, 0.5, 0, 2.0, &out);
  // Acts 0.05 s late, reaches 0.5 m/s after 0.5 s at 1 m/s^2 (0.125 m), then 0.5 m/s.
  EXPECT_NEAR(d.truth().x(), 2.0 + 0.125 + 0.5 * (2.0 - 0.05 - 0.5), 0.011);
  EXPECT_NEAR(d.truth().y(), 1.75, 1e-6);
  EXPECT_TRUE(d.collisions().empty());
  // The ground truth written is where the robot is, every odometry tick.
  const auto truth = out.on("/ground_truth");
  ASSERT_GE(truth.size(), 99u);
  EXPECT_GT(out.on("/scan/s300_front_left").size(), 10u);
  const auto& last = std::get<msg::PoseStamped>(truth.back()->message);
  EXPECT_NEAR(last.pose.position.x, d.truth().x(), 0.011);  // at most one tick (20 ms) behind
  // A quarter turn in place: 90 deg at 0.5 rad/s.
  drive(d, 0, 0.5, 0.1);
  const double yaw0 = d.truth().yaw();
  drive(d, 0, 0.5, M_PI / 2 / 0.5);
  EXPECT_NEAR(std::remainder(d.truth().yaw() - yaw0, 2 * M_PI), M_PI / 2, 0.03);
}

TEST(SimDrive, AWallStopsTheRobotAndIsNamed) {
  Scenario s = navScenario(false);
  s.navigation.start_yaw = -M_PI / 2;  // facing the glass facade at y = 0, 1.75 m away
  Simulator sim(s, loadScenarioMap(s));
  DriveSim d(sim);
  drive(d, 0.3, 0, 8.0);  // 2.4 m: it would pass the facade
  ASSERT_EQ(d.collisions().size(), 1u) << "pushing on is one collision";
  const CollisionEvent& c = d.collisions()[0];
  EXPECT_EQ(c.contact.what, "map");
  EXPECT_EQ(c.contact.label, "wall");  // the facade's parapet under the glass
  EXPECT_LT(c.contact.where.y(), 0.1);
  EXPECT_GT(d.contacts(), 1u);
  // It stands where it last stood clear: its front (0.3 m) just short of the facade.
  EXPECT_GT(d.truth().y(), 0.3);
  EXPECT_LT(d.truth().y(), 0.45);
}

TEST(SimDrive, NoCommandsForHalfASecondStopTheRobot) {
  Scenario s = navScenario(false);
  Simulator sim(s, loadScenarioMap(s));
  DriveSim d(sim);
  drive(d, 0.5, 0, 1.0);
  const double x = d.truth().x();
  test::CaptureWriter sink;
  while (d.nowS() < 3.0) d.step(sink);  // silence
  EXPECT_EQ(d.base().velocity().vx, 0.0);
  EXPECT_EQ(d.base().counters().timeouts, 1u);
  // The last command (0.9 s) acts at 0.95 s; the watchdog fires 0.5 s later: 0.45 s on at
  // 0.5 m/s after t = 1 s, then braking at 1 m/s^2 (0.125 m).
  EXPECT_NEAR(d.truth().x() - x, 0.45 * 0.5 + 0.125, 0.005);
}

TEST(SimDrive, APersonWalkingIntoAStandingRobotIsNotItsCollision) {
  Scenario s = navScenario(false);
  PersonSpec p;
  p.name = "walker";
  p.waypoints = {{2.0, 3.2}, {2.0, 0.4}};  // straight through the robot at (2.0, 1.75)
  p.loop = false;
  p.speed = 1.0;
  s.people.push_back(p);
  Simulator sim(s, loadScenarioMap(s));
  DriveOptions o;
  o.give_way = 0;  // walks on through the robot
  DriveSim d(sim, o);
  drive(d, 0, 0, 4.0);
  EXPECT_TRUE(d.collisions().empty());
  ASSERT_EQ(d.struckBy().size(), 1u);
  EXPECT_EQ(d.struckBy()[0].contact.what, "person");
}

TEST(SimDrive, PeopleWaitWhileTheRobotStandsInTheirWay) {
  Scenario s = navScenario(false);
  PersonSpec p;
  p.name = "walker";
  p.waypoints = {{2.0, 3.2}, {2.0, 0.4}};
  p.loop = false;
  p.speed = 1.0;
  s.people.push_back(p);
  Simulator sim(s, loadScenarioMap(s));
  DriveSim d(sim);  // give_way 1 m
  drive(d, 0, 0, 4.0);
  EXPECT_TRUE(d.collisions().empty());
  EXPECT_TRUE(d.struckBy().empty());
  // Stopped 1 m before the robot's centre (1.75 + 1.0), waiting since about 0.45 s.
  const PersonState st = sim.people().state(0, d.nowS(), {2.0, 1.75});
  EXPECT_NEAR(st.y, 2.75, 0.05);
  ASSERT_EQ(sim.people().delays().size(), 1u);
  EXPECT_NEAR(sim.people().delays()[0], 4.0 - 0.45, 0.1);
  // The robot leaves eastwards: the person walks on.
  drive(d, 0.5, 0, 3.0);
  EXPECT_LT(sim.people().state(0, d.nowS(), {d.truth().x(), d.truth().y()}).y, 2.0);
}

TEST(SimDrive, ARobotDrivingIntoAPersonCollides) {
  Scenario s = navScenario(false);
  PersonSpec p;
  p.name = "standing";
  p.waypoints = {{3.0, 1.75}, {3.0, 1.76}};
  p.loop = false;
  p.speed = 0.01;
  s.people.push_back(p);
  Simulator sim(s, loadScenarioMap(s));
  DriveSim d(sim);
  drive(d, 0.4, 0, 4.0);
  ASSERT_EQ(d.collisions().size(), 1u);
  EXPECT_EQ(d.collisions()[0].contact.what, "person");
  EXPECT_LT(d.truth().x(), 3.0 - 0.3);
}

TEST(SimDrive, BadOptionsNameTheField) {
  Scenario s = navScenario(false);
  Simulator sim(s, loadScenarioMap(s));
  DriveOptions o;
  o.collision_step = 0;
  try {
    DriveSim d(sim, o);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("collision_step"), std::string::npos) << e.what();
  }
  o = {};
  o.command_latency = std::nan("");
  EXPECT_THROW(DriveSim(sim, o), std::invalid_argument);
}

}  // namespace polyloc::t_sim_drive
