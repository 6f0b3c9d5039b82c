// polynav's Controller in closed loop, without polylocd: two 6 x 4 m rooms side by side (a 0.15 m
// wall between them with a 0.75 m door), zones built in code, the Nearness Diagram as the local
// planner (as nav/app/polynav.cpp wires it), a VRS ray-marched from the occupancy grid every
// 0.08 s and a differential robot that moves exactly as commanded with a perfect pose. The robot
// reaches a goal in the other room through the door (never touching a wall, never reversing in
// the door), two goals in sequence (the second backs out first), goes round a danger zone across
// the shortcut, fails with a reason on an unreachable goal and on a timeout, stands still while not
// localised and keeps clear of a person on its way.
#include <polynav/controller.hpp>
#include <polynav/hull.hpp>
#include <polynav/nearness_diagram.hpp>
#include <polynav/zones.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_nav_controller {

using namespace polynav;
using Eigen::Vector2d;
using Eigen::Vector3d;


constexpr double kDeg = M_PI / 180;
constexpr double kDt = 0.08;      // s per VRS
constexpr double kRes = 0.05;     // m per cell
constexpr size_t kBeams = 720;    // over 360 degrees
constexpr double kRangeMax = 8.0;

// ------------------------------------------------------------------------------------- the world
//
//   y
//  4.2 +-----------------------------+-+-----------------------------+
//      |  room a   (0.1..6.1)        |w|  room b   (6.25..12.25)     |
//      |                             | |                             |
//  2.4 |                              door (y 1.65..2.40, x 6.1..6.25)
//  1.65|                             | |                             |
//      |                             | |                             |
//  0   +-----------------------------+-+-----------------------------+--> x
//      outer walls 0.1 m thick; the rooms' floor y 0.1..4.1

constexpr double kWallX0 = 6.1, kWallX1 = 6.25, kDoorY0 = 1.65, kDoorY1 = 2.40;

struct Rect {
  double x0, y0, x1, y1;
};

// Cells whose centre lies in the rectangle become occupied.
void fill(NavGrid& g, const Rect& r) {
  for (size_t iy = 0; iy < g.height; ++iy)
    for (size_t ix = 0; ix < g.width; ++ix) {
      const Vector2d c = g.centre(ix, iy);
      if (c.x() >= r.x0 && c.x() <= r.x1 && c.y() >= r.y0 && c.y() <= r.y1) g.occupied[g.index(ix, iy)] = 1;
    }
}

// The two rooms; `cubicle`: a closed 1.8 x 1.5 m box in room b against its top wall (walls 0.1 m).
LoadedGrid twoRooms(bool cubicle = false) {
  LoadedGrid lg;
  NavGrid& g = lg.grid;
  g.resolution = kRes;
  g.width = 247, g.height = 84;  // 12.35 x 4.2 m
  g.occupied.assign(g.size(), 0);
  fill(g, {0, 0, 12.35, 0.1});
  fill(g, {0, 4.1, 12.35, 4.2});
  fill(g, {0, 0, 0.1, 4.2});
  fill(g, {12.25, 0, 12.35, 4.2});
  fill(g, {kWallX0, 0, kWallX1, kDoorY0});
  fill(g, {kWallX0, kDoorY1, kWallX1, 4.2});
  if (cubicle) {
    fill(g, {9.0, 2.5, 9.1, 4.1});
    fill(g, {10.9, 2.5, 11.0, 4.1});
    fill(g, {9.0, 2.5, 11.0, 2.6});
  }
  return lg;
}

Polygon rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

Zones twoRoomZones() {
  Zones z;
  z.rooms = {{"room a", rect(0.1, 0.1, kWallX0, 4.1)}, {"room b", rect(kWallX1, 0.1, 12.25, 4.1)}};
  Door d;
  d.name = "door ab";
  d.centre = {(kWallX0 + kWallX1) / 2, (kDoorY0 + kDoorY1) / 2};
  d.along = {0, 1};
  d.width = 0.75;
  z.doors = {d};
  return z;
}

GoalSpot goal(const std::string& name, double x, double y, double yaw_deg) {
  GoalSpot g;
  g.name = name;
  g.pose = {x, y, yaw_deg * kDeg};
  g.approach = 0.5;
  return g;
}

bool occupiedAt(const NavGrid& g, const Vector2d& p) {
  const auto c = g.cellAt(p);
  return !c || g.occupied[*c];  // outside the grid counts as a collision too
}

// ---------------------------------------------------------------------------------- the sensors

// A round body in the world (a person's torso) that the VRS sees.
struct Disc {
  Vector2d centre;
  double radius;
};

// The VRS at `pose`: each beam marched through the grid cell by cell (exact cell boundaries)
// to the first occupied cell, and to the discs; nothing within range_max: range_max + 1.
PolarScan vrs(const NavGrid& g, const Vector3d& pose, const std::vector<Disc>& discs = {}) {
  PolarScan s;
  s.angle_increment = 2 * M_PI / double(kBeams);
  s.angle_min = -M_PI + s.angle_increment / 2;  // the VRS's segment centres
  s.range_max = kRangeMax;
  s.ranges.assign(kBeams, float(kRangeMax + 1));
  const double ox = (pose.x() - g.origin_x) / g.resolution, oy = (pose.y() - g.origin_y) / g.resolution;
  for (size_t i = 0; i < kBeams; ++i) {
    const double a = pose.z() + s.angle(i), dx = std::cos(a), dy = std::sin(a);
    // Amanatides & Woo in cell units.
    long cx = long(std::floor(ox)), cy = long(std::floor(oy));
    const long sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
    const double tdx = std::abs(dx) > 1e-12 ? 1.0 / std::abs(dx) : 1e30, tdy = std::abs(dy) > 1e-12 ? 1.0 / std::abs(dy) : 1e30;
    double tx = std::abs(dx) > 1e-12 ? ((dx > 0 ? double(cx + 1) - ox : ox - double(cx)) * tdx) : 1e30;
    double ty = std::abs(dy) > 1e-12 ? ((dy > 0 ? double(cy + 1) - oy : oy - double(cy)) * tdy) : 1e30;
    double t = 0, range = kRangeMax + 1;
    const double tmax = kRangeMax / g.resolution;
    while (t <= tmax) {
      if (cx < 0 || cy < 0 || cx >= long(g.width) || cy >= long(g.height)) break;
      if (g.occupied[g.index(size_t(cx), size_t(cy))]) {
        if (t * g.resolution <= kRangeMax) range = t * g.resolution;
        break;
      }
      if (tx < ty) t = tx, tx += tdx, cx += sx;
      else t = ty, ty += tdy, cy += sy;
    }
    for (const Disc& d : discs) {  // ray-circle
      const Vector2d o = pose.head<2>() - d.centre;
      const double b = o.x() * dx + o.y() * dy, c = o.squaredNorm() - d.radius * d.radius, disc = b * b - c;
      if (disc < 0) continue;
      const double hit = -b - std::sqrt(disc);
      if (hit > 0 && hit < range && hit <= kRangeMax) range = hit;
    }
    s.ranges[i] = float(range);
  }
  return s;
}

// ------------------------------------------------------------------------------------ the robot

// Exact integration of a differential base at (v, w) for dt.
Vector3d integrate(const Vector3d& p, double v, double w, double dt) {
  if (std::abs(w) < 1e-9) return {p.x() + v * dt * std::cos(p.z()), p.y() + v * dt * std::sin(p.z()), p.z()};
  const double th = p.z() + w * dt;
  return {p.x() + v / w * (std::sin(th) - std::sin(p.z())), p.y() - v / w * (std::cos(th) - std::cos(p.z())),
          std::remainder(th, 2 * M_PI)};
}

// The footprint's corners and points along its edges every 2 cm, in the map at `pose`.
std::vector<Vector2d> outline(const Polygon& footprint, const Vector3d& pose) {
  const Polygon placed = placeFootprint(footprint, pose);
  std::vector<Vector2d> out;
  for (size_t k = 0; k < placed.size(); ++k) {
    const Vector2d a = placed[k], b = placed[(k + 1) % placed.size()];
    const int n = std::max(1, int(std::ceil((b - a).norm() / 0.02)));
    for (int j = 0; j < n; ++j) out.push_back(a + (b - a) * (double(j) / n));
  }
  return out;
}

// One recorded step: the input pose and what the controller answered.
struct Step {
  double t;
  Vector3d pose;
  NavOutput out;
};

struct Sim {
  LoadedGrid world;  // what the VRS sees (the map the controller plans on, unless setWorld)
  Zones zones;
  ControllerConfig cfg;
  Controller ctrl;
  Vector3d pose;
  double t = 0;
  bool localised = true;
  std::vector<Person> people;  // what the tracker reports
  std::vector<Disc> bodies;    // what the VRS sees of them
  std::vector<Step> trace;

  Sim(LoadedGrid w, Zones z, ControllerConfig c, const Vector3d& start)
      : world(std::move(w)), zones(z), cfg(std::move(c)), ctrl(world, z, cfg, ndPlanner(cfg)), pose(start) {}

  // The world differs from the map (an obstacle the map does not have).
  void setWorld(LoadedGrid w) { world = std::move(w); }

  static LocalPlanner ndPlanner(const ControllerConfig& cfg) {
    const RectHull hull = RectHull::fromFootprint(cfg.footprint);
    const NdConfig nd{0.3, 90};
    const NdLimits limits{cfg.max_speed, cfg.max_yaw_rate};
    return [=](const PolarScan& s, const Vector2d& goal) {
      const NdCommand c = nearnessDiagram(s, goal, hull, nd, limits);
      return LocalStep{c.v, c.w, situationName(c.situation), c.min_clearance};
    };
  }

  const NavOutput& step() {
    NavInput in;
    in.t = t;
    in.pose = pose;
    in.localised = localised;
    in.scan = vrs(world.grid, pose, bodies);
    in.people = people;
    const NavOutput o = ctrl.update(in);
    trace.push_back({t, pose, o});
    pose = integrate(pose, o.v, o.w, kDt);
    t += kDt;
    return trace.back().out;
  }

  // Steps until `stop` says so (true) or `max_steps` (false).
  bool runUntil(const std::function<bool(const NavOutput&)>& stop, size_t max_steps) {
    for (size_t i = 0; i < max_steps; ++i)
      if (stop(step())) return true;
    return false;
  }

  // The first step whose output says state `state` for goal `g`; none when there is none.
  std::optional<size_t> firstState(int state, size_t g) const {
    for (size_t i = 0; i < trace.size(); ++i)
      if (trace[i].out.state == state && trace[i].out.goal == g) return i;
    return std::nullopt;
  }

  // The last steps as lines: for a failure message.
  std::string tail(size_t n = 12) const {
    std::ostringstream s;
    s.precision(3);
    for (size_t i = trace.size() > n ? trace.size() - n : 0; i < trace.size(); ++i) {
      const Step& st = trace[i];
      s << std::fixed << "t " << st.t << " pose (" << st.pose.x() << ", " << st.pose.y() << ", " << st.pose.z() / kDeg
        << " deg) v " << st.out.v << " w " << st.out.w << " state " << st.out.state << " goal " << st.out.goal << " ["
        << phaseName(st.out.phase) << "] " << st.out.status << "\n";
    }
    return s.str();
  }
};

// Every recorded step: no point of the footprint in an occupied cell. Returns the first offender.
std::optional<size_t> firstCollision(const Sim& sim) {
  for (size_t i = 0; i < sim.trace.size(); ++i)
    for (const Vector2d& p : outline(sim.cfg.footprint, sim.trace[i].pose))
      if (occupiedAt(sim.world.grid, p)) return i;
  return std::nullopt;
}

// In the door region, the commanded v never changes sign: the first step where it does.
std::optional<size_t> doorReversal(const Sim& sim) {
  int sign = 0;
  for (size_t i = 0; i < sim.trace.size(); ++i) {
    const Step& s = sim.trace[i];
    if (!sim.zones.doorAt(s.pose.head<2>())) {
      sign = 0;  // a new passage may go either way
      continue;
    }
    const int sg = s.out.v > 1e-9 ? 1 : s.out.v < -1e-9 ? -1 : 0;
    if (sg == 0) continue;
    if (sign != 0 && sg != sign) return i;
    sign = sg;
  }
  return std::nullopt;
}

double yawError(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

// Wall time of a test body, printed so that slow tests show.
struct Timer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};


// The world as built is what the tests assume: the door fits the robot, the rooms are closed.
TEST(NavController, WorldAndVrsAreWhatTheTestsAssume) {
  const LoadedGrid w = twoRooms();
  const Zones z = twoRoomZones();
  ASSERT_NO_THROW(z.validate());
  EXPECT_FALSE(occupiedAt(w.grid, {6.175, 2.025}));  // the door's centre
  EXPECT_TRUE(occupiedAt(w.grid, {6.175, 1.60}));     // its jambs
  EXPECT_TRUE(occupiedAt(w.grid, {6.175, 2.45}));
  EXPECT_TRUE(occupiedAt(w.grid, {6.175, 1.0}));
  EXPECT_EQ(z.doorAt({6.175, 2.025}), 0u);
  EXPECT_EQ(z.roomAt({3, 2}), "room a");
  EXPECT_EQ(z.roomAt({9, 2}), "room b");
  // The collision check: base_link 0.29 m from the left wall's face puts the rear edge in it, 0.31 m not.
  auto touches = [&](const Vector3d& pose) {
    for (const Vector2d& p : outline(ControllerConfig{}.footprint, pose))
      if (occupiedAt(w.grid, p)) return true;
    return false;
  };
  EXPECT_TRUE(touches({0.1 + 0.29, 2, 0}));
  EXPECT_FALSE(touches({0.1 + 0.31, 2, 0}));
  EXPECT_TRUE(touches({3, 0.1 + 0.24, 0}));           // the side in the bottom wall
  EXPECT_FALSE(touches({6.175, 2.025, 0}));           // centred in the door: 0.125 m each side
  EXPECT_TRUE(touches({6.175, 1.85, 0}));             // 0.175 m off centre: a jamb
  // The VRS from (3, 1, 90 deg): the top wall 3.1 m ahead, the bottom one 0.9 m behind, the
  // left wall (x = 0.1) 2.9 m to the robot's left; beams are segment centres.
  const PolarScan s = vrs(w.grid, {3, 1, M_PI / 2});
  ASSERT_EQ(s.size(), kBeams);
  EXPECT_NEAR(s.angle(0), -M_PI + M_PI / 720, 1e-12);
  const auto ahead = s.indexOf(0.0), behind = s.indexOf(M_PI), left = s.indexOf(M_PI / 2);
  ASSERT_TRUE(ahead && behind && left);
  EXPECT_NEAR(s.ranges[*ahead], 3.1, 0.01);
  EXPECT_NEAR(s.ranges[*behind], 0.9, 0.01);
  EXPECT_NEAR(s.ranges[*left], 2.9, 0.01);
  // Nothing within range: range_max + 1; a disc in front is seen at its surface.
  const PolarScan far = vrs(w.grid, {1, 2, 0});
  EXPECT_FLOAT_EQ(far.ranges[*far.indexOf(0.0)], float(kRangeMax + 1));  // 11 m to room b's far wall
  const PolarScan person = vrs(w.grid, {1, 2, 0}, {{{2.5, 2.0}, 0.2}});
  EXPECT_NEAR(person.ranges[*person.indexOf(0.0)], 1.3, 0.001);
}

TEST(NavController, ReachesAGoalInTheOtherRoomThroughTheDoor) {
  const Timer timer;
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
  const GoalSpot g = goal("room b bench", 10.0, 3.0, 90);
  sim.ctrl.setGoals({g});
  const bool reached = sim.runUntil([](const NavOutput& o) { return o.state != 1; }, 2000);  // 160 s
  ASSERT_TRUE(reached) << "no decision within 160 s\n" << sim.tail();
  const Step& last = sim.trace.back();
  ASSERT_EQ(last.out.state, 2) << last.out.status << "\n" << sim.tail();
  EXPECT_EQ(last.out.goal, 0u);
  EXPECT_EQ(last.out.phase, Phase::Reached);
  EXPECT_NE(last.out.status.find("'room b bench' reached"), std::string::npos) << last.out.status;
  EXPECT_NE(last.out.status.find("room b"), std::string::npos) << last.out.status;
  EXPECT_LE((last.pose.head<2>() - g.pose.head<2>()).norm(), 0.02)
      << "final (" << last.pose.x() << ", " << last.pose.y() << ")";
  EXPECT_LE(yawError(last.pose.z(), g.pose.z()), 1 * kDeg) << "final yaw " << last.pose.z() / kDeg << " deg";
  // It went through the door, passing it in phases: align, then pass.
  bool aligned = false, passed = false, in_door = false;
  for (const Step& s : sim.trace) {
    aligned |= s.out.phase == Phase::DoorAlign;
    passed |= s.out.phase == Phase::DoorPass;
    in_door |= sim.zones.doorAt(s.pose.head<2>()).has_value();
  }
  EXPECT_TRUE(aligned && passed && in_door);
  // Never a part of the footprint in a wall; never reversing in the door.
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
  if (auto r = doorReversal(sim)) ADD_FAILURE() << "v changed sign in the door at t " << sim.trace[*r].t;
  EXPECT_LT(timer.seconds(), 20.0);
  std::printf("  reached after %.1f s simulated (%zu steps), final error %.4f m %.3f deg, %.2f s wall\n", last.t,
              sim.trace.size(), (last.pose.head<2>() - g.pose.head<2>()).norm(), yawError(last.pose.z(), g.pose.z()) / kDeg,
              timer.seconds());
}

TEST(NavController, TwoGoalsInSequenceTheSecondBacksOutFirst) {
  const Timer timer;
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
  const GoalSpot g0 = goal("room b bench", 10.0, 3.0, 90), g1 = goal("room a shelf", 1.5, 3.0, 180);
  sim.ctrl.setGoals({g0, g1});
  const bool done = sim.runUntil([](const NavOutput& o) { return o.state == 3 || (o.state == 2 && o.goal == 1); }, 4000);
  ASSERT_TRUE(done) << "not done within 320 s\n" << sim.tail();
  ASSERT_EQ(sim.trace.back().out.state, 2) << sim.trace.back().out.status << "\n" << sim.tail();
  const auto r0 = sim.firstState(2, 0), r1 = sim.firstState(2, 1);
  ASSERT_TRUE(r0 && r1);
  // At the first goal within tolerance.
  EXPECT_LE((sim.trace[*r0].pose.head<2>() - g0.pose.head<2>()).norm(), 0.02);
  EXPECT_LE(yawError(sim.trace[*r0].pose.z(), g0.pose.z()), 1 * kDeg);
  // Held there ~1 s (standing), then the second goal starts with the Leave phase, backing out.
  std::optional<size_t> first1;
  for (size_t i = *r0; i < sim.trace.size(); ++i)
    if (sim.trace[i].out.goal == 1 && sim.trace[i].out.state == 1) {
      first1 = i;
      break;
    }
  ASSERT_TRUE(first1);
  EXPECT_NEAR(sim.trace[*first1].t - sim.trace[*r0].t, cfg.hold, 2 * kDt);
  for (size_t i = *r0; i < *first1; ++i) EXPECT_EQ(sim.trace[i].out.v, 0.0) << "moved while holding at t " << sim.trace[i].t;
  EXPECT_EQ(sim.trace[*first1].out.phase, Phase::Leave) << phaseName(sim.trace[*first1].out.phase);
  EXPECT_LT(sim.trace[*first1].out.v, 0.0);
  // Backed out along the goal's heading (-y here) to about the approach pose, then drove on.
  size_t leave_end = *first1;
  while (leave_end < sim.trace.size() && sim.trace[leave_end].out.phase == Phase::Leave) ++leave_end;
  ASSERT_LT(leave_end, sim.trace.size());
  const Vector3d backed = sim.trace[leave_end].pose;
  EXPECT_NEAR(backed.y(), approachPose(g0).y(), 0.03);
  EXPECT_NEAR(backed.x(), g0.pose.x(), 0.02);
  // The second goal reached within tolerance, after the door again.
  const Step& last = sim.trace[*r1];
  EXPECT_LE((last.pose.head<2>() - g1.pose.head<2>()).norm(), 0.02)
      << "final (" << last.pose.x() << ", " << last.pose.y() << ")";
  EXPECT_LE(yawError(last.pose.z(), g1.pose.z()), 1 * kDeg) << last.pose.z() / kDeg;
  EXPECT_NE(last.out.status.find("'room a shelf' reached"), std::string::npos) << last.out.status;
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
  if (auto r = doorReversal(sim)) ADD_FAILURE() << "v changed sign in the door at t " << sim.trace[*r].t;
  EXPECT_LT(timer.seconds(), 20.0);
  std::printf("  goal 0 at %.1f s, goal 1 at %.1f s simulated, %.2f s wall\n", sim.trace[*r0].t, last.t, timer.seconds());
}

TEST(NavController, DangerZoneAcrossTheShortcutIsGoneAround) {
  const Timer timer;
  ControllerConfig cfg;
  Zones z = twoRoomZones();
  // Across room a from the bottom wall to y = 2.6, between the start and the goal.
  z.danger = {{"spill", rect(2.6, 0.1, 3.4, 2.6)}};
  ASSERT_NO_THROW(z.validate());
  Sim sim(twoRooms(), z, cfg, {1.0, 1.0, 0.0});
  const GoalSpot g = goal("room a desk", 5.0, 1.0, 0);
  ASSERT_FALSE(z.inDanger(cfg.footprint, g.pose));
  sim.ctrl.setGoals({g});
  const bool decided = sim.runUntil([](const NavOutput& o) { return o.state != 1; }, 2000);
  ASSERT_TRUE(decided) << sim.tail();
  const Step& last = sim.trace.back();
  ASSERT_EQ(last.out.state, 2) << last.out.status << "\n" << sim.tail();
  EXPECT_LE((last.pose.head<2>() - g.pose.head<2>()).norm(), 0.02);
  EXPECT_LE(yawError(last.pose.z(), g.pose.z()), 1 * kDeg);
  double top = -1;
  for (const Step& s : sim.trace) {
    ASSERT_FALSE(sim.zones.inDanger(cfg.footprint, s.pose))
        << "footprint in the danger zone at t " << s.t << " pose (" << s.pose.transpose() << ")\n" << sim.tail();
    if (s.pose.x() > 2.6 && s.pose.x() < 3.4) top = std::max(top, s.pose.y());
  }
  EXPECT_GT(top, 2.6 + 0.25);  // it went round above the zone
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
  EXPECT_LT(timer.seconds(), 20.0);
  std::printf("  reached after %.1f s simulated, %.2f s wall\n", last.t, timer.seconds());
}


// The first step whose phase is Failed: the step on which the controller decided.
std::optional<size_t> firstFailed(const Sim& sim) {
  for (size_t i = 0; i < sim.trace.size(); ++i)
    if (sim.trace[i].out.phase == Phase::Failed) return i;
  return std::nullopt;
}

// Room a's door closed by a leaf the map does not have (the VRS sees it, the plan goes through).
LoadedGrid closedDoorWorld() {
  LoadedGrid w = twoRooms();
  fill(w.grid, {kWallX0, kDoorY0, kWallX1, kDoorY1});
  return w;
}


TEST(NavController, UnreachableGoalFailsAtOnceWithTheReason) {
  ControllerConfig cfg;
  Sim sim(twoRooms(true), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
  sim.ctrl.setGoals({goal("in the cubicle", 10.0, 3.5, 90)});  // inside the closed box in room b
  const bool decided = sim.runUntil([](const NavOutput& o) { return o.state == 3; }, 50);
  ASSERT_TRUE(decided) << sim.tail();
  // Decided on the first step, standing: the reason is in that step's status.
  const auto f = firstFailed(sim);
  ASSERT_TRUE(f);
  EXPECT_EQ(*f, 0u);
  const NavOutput& why = sim.trace[*f].out;
  EXPECT_NE(why.status.find("'in the cubicle' failed: no path: goal unreachable from the start"), std::string::npos)
      << why.status;
  EXPECT_EQ(why.v, 0.0);
  EXPECT_EQ(why.w, 0.0);
  // State 3 follows at once.
  const NavOutput& o = sim.trace.back().out;
  EXPECT_LE(sim.trace.size(), 2u);
  EXPECT_EQ(o.phase, Phase::Failed);
  EXPECT_EQ(o.goal, 0u);
  EXPECT_NE(o.status.find("'in the cubicle' failed"), std::string::npos) << o.status;
  EXPECT_EQ(o.v, 0.0);
  EXPECT_EQ(o.w, 0.0);
  EXPECT_EQ(sim.pose, Vector3d(1.5, 1.0, 0.0));
  // Then all goals are done: idle, standing.
  const NavOutput& after = sim.step();
  EXPECT_TRUE(sim.ctrl.done());
  EXPECT_EQ(after.state, 0);
  EXPECT_EQ(after.v, 0.0);
}

TEST(NavController, ClosedDoorSeenAheadFailsNamingTheDoor) {
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
  sim.setWorld(closedDoorWorld());
  sim.ctrl.setGoals({goal("room b bench", 10.0, 3.0, 90)});
  const bool decided = sim.runUntil([](const NavOutput& o) { return o.state == 3; }, 500);  // 40 s
  ASSERT_TRUE(decided) << sim.tail();
  const auto f = firstFailed(sim);
  ASSERT_TRUE(f);
  EXPECT_NE(sim.trace[*f].out.status.find("failed: door 'door ab' closed"), std::string::npos) << sim.trace[*f].out.status;
  EXPECT_LT(sim.trace[*f].t, 15.0);
  EXPECT_EQ(sim.trace.back().out.v, 0.0);
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall or the leaf at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
}

// follow()'s failures ("no path", "path blocked", "door closed") go out with state 3 and the reason
// in the same command (a consumer reading the state, as eval nav does, learns why).
TEST(NavController, FailureStateComesWithTheReason) {
  ControllerConfig cfg;
  {
    Sim sim(twoRooms(true), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
    sim.ctrl.setGoals({goal("in the cubicle", 10.0, 3.5, 90)});
    ASSERT_TRUE(sim.runUntil([](const NavOutput& o) { return o.state == 3; }, 50)) << sim.tail();
    const NavOutput& o = sim.trace.back().out;
    EXPECT_NE(o.status.find("no path: goal unreachable from the start"), std::string::npos) << o.status;
    for (const Step& s : sim.trace) EXPECT_FALSE(s.out.phase == Phase::Failed && s.out.state != 3) << s.out.status;
  }
  {
    Sim sim(twoRooms(), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
    sim.setWorld(closedDoorWorld());
    sim.ctrl.setGoals({goal("room b bench", 10.0, 3.0, 90)});
    ASSERT_TRUE(sim.runUntil([](const NavOutput& o) { return o.state == 3; }, 500)) << sim.tail();
    const NavOutput& o = sim.trace.back().out;
    EXPECT_NE(o.status.find("door 'door ab' closed"), std::string::npos) << o.status;
    for (const Step& s : sim.trace) EXPECT_FALSE(s.out.phase == Phase::Failed && s.out.state != 3) << s.out.status;
  }
}

// Starting within 2 m of a door that is closed (a leaf the map lacks), the controller aligns and
// starts the passage; the guard stops it before the leaf; the door is reported closed or blocked
// well before the mission timeout, without touching it.
TEST(NavController, ClosedDoorFoundWhileAligningIsReported) {
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {4.2, 2.0, 0.0});
  sim.setWorld(closedDoorWorld());
  sim.ctrl.setGoals({goal("room b bench", 10.0, 3.0, 90)});
  ASSERT_TRUE(sim.runUntil([](const NavOutput& o) { return o.state == 3; }, 1600)) << sim.tail();
  const auto f = firstFailed(sim);
  ASSERT_TRUE(f);
  const std::string& why = sim.trace[*f].out.status;
  EXPECT_TRUE(why.find("door 'door ab' closed") != std::string::npos || why.find("door 'door ab' blocked") != std::string::npos) << why;
  EXPECT_LT(sim.trace[*f].t, cfg.wait_blocked + 10);
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall or the leaf at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
}

// The approach pose of a goal facing away from a wall, 0.1 m clear of it with the whole footprint
// (so plannable), is driven at forwards, facing the wall: the guard must let the robot reach it.
TEST(NavController, GoalFacingAwayFromAWallIsReached) {
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {3.0, 2.0, 0.0});
  const GoalSpot g = goal("by the wall", 1.0, 2.0, 0);
  // The approach pose's footprint is clear of the wall (x = 0.1) by 0.1 m.
  ASSERT_FALSE(occupiedAt(sim.world.grid, {0.5 - 0.3 - 0.09, 2.0}));
  sim.ctrl.setGoals({g});
  ASSERT_TRUE(sim.runUntil([](const NavOutput& o) { return o.state != 1; }, 1600)) << sim.tail();
  const Step& last = sim.trace.back();
  ASSERT_EQ(last.out.state, 2) << last.out.status << "\n" << sim.tail();
  EXPECT_LE((last.pose.head<2>() - g.pose.head<2>()).norm(), 0.02);
  EXPECT_LE(yawError(last.pose.z(), g.pose.z()), 1 * kDeg);
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
}

TEST(NavController, MissionTimeoutFails) {
  ControllerConfig cfg;
  cfg.mission_timeout = 4.0;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
  sim.ctrl.setGoals({goal("room b bench", 10.0, 3.0, 90)});
  const bool decided = sim.runUntil([](const NavOutput& o) { return o.state != 1; }, 200);
  ASSERT_TRUE(decided) << sim.tail();
  const Step& last = sim.trace.back();
  EXPECT_EQ(last.out.state, 3);
  EXPECT_NE(last.out.status.find("timeout"), std::string::npos) << last.out.status;
  EXPECT_GT(last.t, 4.0);
  EXPECT_LE(last.t, 4.0 + 2 * kDt);
  EXPECT_EQ(last.out.v, 0.0);
  EXPECT_EQ(last.out.w, 0.0);
  // It was driving before.
  double moved = (last.pose.head<2>() - Vector2d(1.5, 1.0)).norm();
  EXPECT_GT(moved, 0.3);
}

TEST(NavController, NotLocalisedStandsStill) {
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {1.5, 1.0, 0.0});
  sim.ctrl.setGoals({goal("room a desk", 5.0, 1.0, 0)});
  sim.localised = false;
  for (int i = 0; i < 50; ++i) {
    const NavOutput& o = sim.step();
    ASSERT_EQ(o.v, 0.0) << "step " << i;
    ASSERT_EQ(o.w, 0.0) << "step " << i;
    EXPECT_NE(o.status.find("localisation"), std::string::npos) << o.status;
    EXPECT_NE(o.state, 3);
  }
  EXPECT_EQ(sim.pose, Vector3d(1.5, 1.0, 0.0));
  // Localised again: it drives.
  sim.localised = true;
  bool drove = false;
  for (int i = 0; i < 50 && !drove; ++i) drove = sim.step().v > 0.05;
  EXPECT_TRUE(drove) << sim.tail();
}


// The goal straight ahead of the start in room a, a person standing on the straight line
// between; `visible`: the VRS sees the person's body (a 0.2 m disc) too, not only the tracker.
void personOnThePath(bool visible) {
  const Timer timer;
  ControllerConfig cfg;
  Sim sim(twoRooms(), twoRoomZones(), cfg, {0.8, 1.5, 0.0});
  const Vector2d person(2.9, 1.5);
  sim.people = {{person, {0, 0}}};
  if (visible) sim.bodies = {{person, 0.2}};
  const GoalSpot g = goal("room a desk", 5.0, 1.5, 0);
  sim.ctrl.setGoals({g});
  sim.runUntil([](const NavOutput& o) { return o.state != 1; }, 1500);  // 120 s
  double closest = 1e9, closest_t = 0;
  for (const Step& s : sim.trace) {
    const double d = polygonDistance(placeFootprint(cfg.footprint, s.pose), person);
    if (d < closest) closest = d, closest_t = s.t;
  }
  EXPECT_GE(closest, cfg.person_radius - 0.05) << "came within " << closest << " m of the person at t " << closest_t;
  const Step& last = sim.trace.back();
  // Reached, or (allowed) still waiting in front of the person at the end, never failed.
  EXPECT_NE(last.out.state, 3) << last.out.status << "\n" << sim.tail();
  if (last.out.state == 2) {
    EXPECT_LE((last.pose.head<2>() - g.pose.head<2>()).norm(), 0.02);
    EXPECT_LE(yawError(last.pose.z(), g.pose.z()), 1 * kDeg);
  }
  EXPECT_EQ(last.out.state, 2) << "not reached (waiting is allowed but not expected here)\n" << sim.tail();
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
  EXPECT_LT(timer.seconds(), 20.0);
  std::printf("  %s after %.1f s simulated, closest %.3f m to the person, %.2f s wall\n",
              last.out.state == 2 ? "reached" : "not reached", last.t, closest, timer.seconds());
}


TEST(NavController, PersonOnThePathSeenByTheVrsIsKeptClear) { personOnThePath(true); }

TEST(NavController, PersonOnThePathOnlyTrackedIsKeptClear) { personOnThePath(false); }

// Cells closed for an obstacle the map lacks open again after the controller's plan.blocked_max_age_s
// (docs/navigation.md: 30 s by default), counted from when they were last seen blocked: a box on
// the way in room a is seen and gone round; 6 s after the robot entered room b (the box behind,
// out of sight of the path check, and a replan in between) the cells are open again with a 2 s age
// and still closed with the default.
struct BlockedRun {
  size_t blocked_max = 0;    // the most cells closed at once
  size_t blocked_later = 0;  // cells closed 6 s after entering room b
  bool measured = false;     // the run lasted until then
  int state = 0;
};

BlockedRun runPastABox(const ControllerConfig& cfg) {
  Sim sim(twoRooms(), twoRoomZones(), cfg, {1.0, 1.0, 0.0});
  LoadedGrid w = twoRooms();
  fill(w.grid, {3.2, 1.0, 3.6, 1.9});
  sim.setWorld(std::move(w));
  sim.ctrl.setGoals({goal("room b bench", 10.0, 3.0, 90)});
  BlockedRun r;
  double in_b = -1;
  for (size_t i = 0; i < 2500; ++i) {
    const NavOutput& o = sim.step();
    r.state = o.state;
    r.blocked_max = std::max(r.blocked_max, sim.ctrl.blockedCells());
    if (in_b < 0 && sim.pose.x() > kWallX1 + 0.5) in_b = sim.t;
    if (in_b >= 0 && sim.t >= in_b + 6.0) {
      r.blocked_later = sim.ctrl.blockedCells();
      r.measured = true;
      break;
    }
    if (o.state != 1) break;
  }
  EXPECT_GE(in_b, 0) << "never reached room b\n" << sim.tail();
  if (auto c = firstCollision(sim))
    ADD_FAILURE() << "footprint in a wall or the box at t " << sim.trace[*c].t << " pose (" << sim.trace[*c].pose.transpose() << ")";
  return r;
}

TEST(NavController, BlockedCellsOpenAgainAfterTheConfiguredAge) {
  ControllerConfig quick;
  quick.plan.blocked_max_age_s = 2.0;
  const BlockedRun a = runPastABox(quick);
  ASSERT_GT(a.blocked_max, 0u) << "the box was never seen on the path";
  ASSERT_TRUE(a.measured) << "the run ended before 6 s in room b";
  EXPECT_EQ(a.blocked_later, 0u) << "cells still closed in room b with a 2 s age";
  EXPECT_EQ(a.state, 1) << "the mission should still be under way";
  const BlockedRun d = runPastABox(ControllerConfig{});
  ASSERT_GT(d.blocked_max, 0u);
  ASSERT_TRUE(d.measured);
  EXPECT_GT(d.blocked_later, 0u) << "cells opened in room b with the default 30 s age";
  EXPECT_THROW(Controller(twoRooms(), twoRoomZones(), [] {
                 ControllerConfig c;
                 c.plan.blocked_max_age_s = -1;
                 return c;
               }(), Sim::ndPlanner(ControllerConfig{})),
               std::invalid_argument);
}

}  // namespace polyloc::t_nav_controller
