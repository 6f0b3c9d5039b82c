// Paths, speed profiles and trajectories of the simulator (kernels/sim/path, profile, trajectory).
#include <polyloc/geometry/pose.hpp>
#include <polyloc/sim/path.hpp>
#include <polyloc/sim/profile.hpp>
#include <polyloc/sim/trajectory.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_path {

using namespace polyloc;
using V2 = Eigen::Vector2d;

Waypoint wp(double x, double y, std::optional<double> heading = {}, double wait = 0) {
  Waypoint w;
  w.p = {x, y}, w.heading = heading, w.wait = wait;
  return w;
}
std::vector<V2> zigzag() { return {{0, 0}, {2, 0}, {3, 1.5}, {3.2, 4}, {1, 5}, {-1, 4}}; }

TEST(SimPath, DensifyKeepsPointsAndSpacing) {
  std::vector<int> index;
  const auto d = densifyPolyline({{0, 0}, {1.2, 0}, {1.2, 0}, {1.2, 0.3}}, 0.5, &index);
  ASSERT_EQ(index.size(), 4u);
  EXPECT_EQ(index[0], 0);
  EXPECT_EQ(index[2], -1);  // duplicate dropped
  EXPECT_TRUE(d[index[1]].isApprox(V2(1.2, 0)));
  EXPECT_TRUE(d[index[3]].isApprox(V2(1.2, 0.3)));
  for (size_t i = 1; i < d.size(); ++i) EXPECT_LE((d[i] - d[i - 1]).norm(), 0.5 + 1e-12);
}

TEST(SimPath, SplinePassesThroughWaypoints) {
  const auto pts = densifyPolyline(zigzag(), 0.4);
  const SplinePath p(pts);
  ASSERT_EQ(p.numKnots(), pts.size());
  for (size_t i = 0; i < pts.size(); ++i) EXPECT_LT((p.position(p.knotS(i)) - pts[i]).norm(), 1e-9) << i;
  EXPECT_LT((p.position(0) - pts.front()).norm(), 1e-12);
  EXPECT_LT((p.position(p.length()) - pts.back()).norm(), 1e-9);
  // Natural ends: no curvature at the first and last point.
  EXPECT_NEAR(p.curvature(0), 0.0, 1e-9);
  EXPECT_NEAR(p.curvature(p.length()), 0.0, 1e-6);
}

TEST(SimPath, SplineIsC2AtKnots) {
  const SplinePath p(densifyPolyline(zigzag(), 0.7));
  double t = 0;
  for (size_t i = 1; i + 1 < p.numKnots(); ++i) {
    t += (p.knot(i) - p.knot(i - 1)).norm();  // knots sit at cumulative chord length
    const double h = 1e-7;
    for (int order = 0; order <= 2; ++order) {
      const V2 left = p.evalT(t - h, order), right = p.evalT(t + h, order);
      EXPECT_LT((left - right).norm(), 1e-5) << "knot " << i << " derivative " << order;
    }
    // The third derivative jumps (a cubic per segment), which makes the check above meaningful.
  }
  // Finite differences of the arc-length parametrised curve: the second derivative just before
  // and just after a knot agree (a C1 spline would jump there by about its curvature, ~1/m).
  for (size_t i = 1; i + 1 < p.numKnots(); ++i) {
    const double s = p.knotS(i), h = 1e-5, delta = 1e-4;
    auto second = [&](double c) -> V2 { return (p.position(c + h) - 2 * p.position(c) + p.position(c - h)) / (h * h); };
    EXPECT_LT((second(s - delta) - second(s + delta)).norm(), 0.01) << i;
  }
}

TEST(SimPath, ArcLengthParametrisation) {
  const SplinePath p(densifyPolyline(zigzag(), 0.5));
  const double h = 1e-4;
  for (double s = h; s < p.length() - h; s += p.length() / 397) {
    const double speed = (p.position(s + h) - p.position(s - h)).norm() / (2 * h);
    ASSERT_NEAR(speed, 1.0, 1e-6) << "s = " << s;
    ASSERT_NEAR(p.tangent(s).norm(), 1.0, 1e-12);
  }
  // The length is the integral of the speed: compare with a fine polyline.
  double poly = 0;
  const int n = 200000;
  for (int k = 1; k <= n; ++k) poly += (p.position(p.length() * k / n) - p.position(p.length() * (k - 1) / n)).norm();
  EXPECT_NEAR(poly, p.length(), 1e-6);
}

TEST(SimPath, StraightLineAndErrors) {
  const SplinePath p({{1, 1}, {4, 5}});
  EXPECT_NEAR(p.length(), 5.0, 1e-12);
  EXPECT_TRUE(p.position(2.5).isApprox(V2(2.5, 3.0)));
  EXPECT_NEAR(p.curvature(1.0), 0.0, 1e-12);
  EXPECT_THROW(SplinePath({{1, 1}, {1, 1}}), std::invalid_argument);
}

TEST(SimProfile, RespectsSpeedAndAccelerationLimits) {
  const SpeedLimits lim{0.8, 0.5};
  auto cap = [](double s) { return s > 3 && s < 4 ? 0.3 : 1e9; };  // a slow zone
  const SpeedProfile prof(10.0, lim, cap);
  EXPECT_EQ(prof.at(0).v, 0.0);
  EXPECT_EQ(prof.at(prof.duration()).s, 10.0);
  EXPECT_EQ(prof.at(prof.duration() + 1).v, 0.0);
  double prev_v = 0, prev_s = 0, max_v = 0;
  const double dt = 1e-3;
  for (double t = dt; t <= prof.duration(); t += dt) {
    const auto st = prof.at(t);
    ASSERT_LE(st.v, lim.max_speed + 1e-9);
    ASSERT_LE(std::abs(st.v - prev_v) / dt, lim.max_acceleration + 1e-6) << t;
    ASSERT_GE(st.s, prev_s);
    ASSERT_NEAR((st.s - prev_s) / dt, 0.5 * (st.v + prev_v), 1e-4);  // s' = v
    if (st.s > 3.01 && st.s < 3.99) {
      ASSERT_LE(st.v, 0.3 + 1e-9);
    }
    max_v = std::max(max_v, st.v);
    prev_v = st.v, prev_s = st.s;
  }
  EXPECT_NEAR(max_v, lim.max_speed, 1e-9);  // reaches the limit on the long stretch
  // Time-optimal trapezoid on a straight line: accelerate, cruise, brake.
  const SpeedProfile line(10.0, lim);
  const double ta = 0.8 / 0.5, da = 0.5 * 0.5 * ta * ta;
  EXPECT_NEAR(line.duration(), 2 * ta + (10 - 2 * da) / 0.8, 1e-6);
}

TEST(SimTrajectory, DifferentialFollowsTangentWithinLimits) {
  RouteSpec r;
  for (const V2& p : zigzag()) r.waypoints.push_back(wp(p.x(), p.y()));
  r.max_speed = 0.6, r.max_acceleration = 0.4, r.max_yaw_rate = 0.7, r.max_lateral_acceleration = 0.3;
  r.start_pause = 0.5;
  const Trajectory traj(r, Kinematics::Differential);
  EXPECT_GT(traj.duration(), traj.length() / r.max_speed);
  const double dt = 0.002;
  PlanarState prev = traj.at(0);
  double prev_v = 0;
  for (double t = dt; t <= traj.duration() + 0.5; t += dt) {
    const PlanarState st = traj.at(t);
    const double v = std::hypot(st.vx, st.vy);
    ASSERT_LE(v, r.max_speed + 1e-9);
    ASSERT_LE(std::abs(v - prev_v) / dt, r.max_acceleration + 1e-3) << t;
    ASSERT_LE(std::abs(st.omega), r.max_yaw_rate + 1e-3) << t;
    ASSERT_LE(v * v * std::abs(st.omega / std::max(v, 1e-9)), r.max_lateral_acceleration + 1e-3);
    if (v > 0.05) {
      ASSERT_NEAR(angleDiff(st.yaw, std::atan2(st.vy, st.vx)), 0.0, 1e-6);  // faces along the path
    }
    ASSERT_LE(std::hypot(st.x - prev.x, st.y - prev.y), r.max_speed * dt + 1e-9);
    prev = st, prev_v = v;
  }
  const PlanarState end = traj.at(traj.duration() + 10);
  EXPECT_NEAR(end.x, -1, 1e-9);
  EXPECT_NEAR(end.y, 4, 1e-9);
  EXPECT_EQ(traj.at(0.4).x, 0.0);  // still pausing
}

TEST(SimTrajectory, StopsWaitsAndTurnsInPlace) {
  RouteSpec r;
  r.waypoints = {wp(0, 0), wp(2, 0), wp(4, 0, {}, 2.0), wp(4, 3)};
  r.start_pause = 0;
  r.max_yaw_rate = 1.0, r.max_yaw_acceleration = 2.0;
  const Trajectory traj(r, Kinematics::Differential);
  ASSERT_EQ(traj.numLegs(), 2u);
  // Find the arrival at (4, 0): it waits 2 s there, facing east, then turns left by 90 deg.
  double arrive = -1;
  for (double t = 0; t < traj.duration(); t += 0.001)
    if (traj.at(t).x >= 4 - 1e-9) {
      arrive = t;
      break;
    }
  ASSERT_GT(arrive, 0);
  EXPECT_NEAR(traj.at(arrive + 1.0).yaw, 0.0, 1e-9);
  EXPECT_NEAR(traj.at(arrive + 1.9).x, 4.0, 1e-9);
  const PlanarState turning = traj.at(arrive + 2.0 + 0.5);
  EXPECT_GT(turning.yaw, 0.0);
  EXPECT_LT(turning.yaw, M_PI / 2);
  EXPECT_NEAR(turning.x, 4.0, 1e-9);
  // Turn of 90 deg at 1 rad/s, 2 rad/s^2: 0.5 s up, (pi/2 - 0.5) s at full rate, 0.5 s down.
  const double turn_end = arrive + 2.0 + 1.0 + (M_PI / 2 - 0.5);
  EXPECT_NEAR(traj.at(turn_end + 0.01).yaw, M_PI / 2, 1e-6);
  EXPECT_NEAR(traj.at(turn_end - 0.25).omega, 0.5, 1e-3);
}

TEST(SimTrajectory, OmniKeepsGivenHeading) {
  RouteSpec r;
  r.waypoints = {wp(0, 0, 0.0), wp(3, 0), wp(3, 3, M_PI / 2)};
  r.start_pause = 0;
  const Trajectory traj(r, Kinematics::Omni);
  EXPECT_NEAR(traj.at(0).yaw, 0.0, 1e-12);
  EXPECT_NEAR(traj.at(traj.duration()).yaw, M_PI / 2, 1e-9);
  double prev = 0;
  for (double t = 0.01; t < traj.duration(); t += 0.01) {
    const PlanarState st = traj.at(t);
    ASSERT_GE(st.yaw, prev - 1e-12);  // turns steadily from 0 to 90 deg while driving
    ASSERT_LE(std::abs(st.omega), r.max_yaw_rate + 1e-6);
    prev = st.yaw;
  }
  r.heading = 0.3;  // a fixed heading overrides the waypoints'
  const Trajectory fixed(r, Kinematics::Omni);
  for (double t = 0; t < fixed.duration(); t += 0.5) EXPECT_NEAR(fixed.at(t).yaw, 0.3, 1e-12);
}

}  // namespace polyloc::t_sim_path
