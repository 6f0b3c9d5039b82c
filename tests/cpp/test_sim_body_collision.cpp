#include <polyloc/sim/body_collision.hpp>
#include <polyloc/sim/convex_overlap.hpp>

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_body_collision {

using namespace polyloc;


RobotSpec rect(double lx, double ly, double height) {
  RobotSpec r;
  r.footprint = {{lx / 2, ly / 2}, {-lx / 2, ly / 2}, {-lx / 2, -ly / 2}, {lx / 2, -ly / 2}};
  r.height = height;
  return r;
}

// Room interior [-3, 3] x [-2, 2] x [0, 2.5]; a table top with no legs and a chair seat in it.
Mesh furnishedRoom() {
  Mesh m = test::boxRoom(3.f, 2.f, 2.5f, 0.2f);
  mapgen::MeshBuilder b(m);
  b.box({1.0f, -0.5f, 0.70f}, {2.0f, 0.5f, 0.73f}, "table");
  b.box({-2.0f, -0.25f, 0.45f}, {-1.5f, 0.25f, 0.5f}, "chair");
  return m;
}

// Lowest triangle overlapping the body, without the broad phase.
uint32_t bruteForce(const Mesh& m, const BodyCollider& c, const Pose& p, double clearance, double height) {
  for (uint32_t t = 0; t < m.numTriangles(); ++t) {
    const auto v = [&](int k) { return Eigen::Vector3d(m.vertices[m.triangles[t][k]].cast<double>()); };
    const ConvexShape tri = ConvexShape::triangle(v(0), v(1), v(2));
    for (const auto& piece : c.pieces())
      if (overlap(ConvexShape::prism(piece, p.z() + clearance, p.z() + height, {p.x(), p.y()}, p.yaw()), tri)) return t;
  }
  return kNoBodyTriangle;
}

void expectWithinBody(const BodyContact& c, const Pose& p, double reach, double height) {
  EXPECT_LE(std::abs(c.where.x() - p.x()), reach + 1e-9);
  EXPECT_LE(std::abs(c.where.y() - p.y()), reach + 1e-9);
  EXPECT_GE(c.where.z(), p.z() + 0.02 - 1e-9);
  EXPECT_LE(c.where.z(), p.z() + height + 1e-9);
}


TEST(SimBodyCollision, WallsOfTheRoom) {
  const Mesh m = furnishedRoom();
  const BodyCollider body(m, rect(0.6, 0.5, 1.2));
  EXPECT_FALSE(body.check(Pose::planar(0, 0, 0)).hit);  // the floor under it is no contact
  EXPECT_FALSE(body.check(Pose::planar(2.69, 0, 0)).hit);  // front edge 1 cm short of the wall
  const BodyContact c = body.check(Pose::planar(2.71, 0, 0));  // 1 cm into it
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.what, "map");
  EXPECT_EQ(c.label, "wall");
  ASSERT_LT(c.triangle, m.numTriangles());
  EXPECT_EQ(m.labelOf(c.triangle), "wall");
  EXPECT_NEAR(c.where.x(), 3.0, 1e-6);  // on the wall's face
  expectWithinBody(c, Pose::planar(2.71, 0, 0), 0.3, 1.2);
}

TEST(SimBodyCollision, TheFloorCountsOnlyWithoutClearance) {
  const Mesh m = furnishedRoom();
  const BodyContact c = BodyCollider(m, rect(0.6, 0.5, 1.2), 0.0).check(Pose::planar(0, 0, 0));
  EXPECT_TRUE(c.hit);  // body bottom touching the floor's top: touching is contact
  EXPECT_EQ(c.label, "floor");
  EXPECT_FALSE(BodyCollider(m, rect(0.6, 0.5, 1.2), 0.02).check(Pose::fromXYZRPY(0, 0, -0.019, 0, 0, 0)).hit);
  EXPECT_TRUE(BodyCollider(m, rect(0.6, 0.5, 1.2), 0.02).check(Pose::fromXYZRPY(0, 0, -0.021, 0, 0, 0)).hit);
}

TEST(SimBodyCollision, TableTopAtBodyHeightNotUnderALowRobot) {
  const Mesh m = furnishedRoom();
  const BodyCollider tall(m, rect(0.6, 0.5, 1.2)), low(m, rect(0.6, 0.5, 0.6));
  const BodyContact c = tall.check(Pose::planar(1.5, 0, 0));
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.label, "table");
  EXPECT_GE(c.where.z(), 0.70 - 1e-6);
  EXPECT_LE(c.where.z(), 0.73 + 1e-6);
  EXPECT_FALSE(low.check(Pose::planar(1.5, 0, 0)).hit);
  // Driving towards the table: the tall robot's front edge meets the table's edge at x = 1.
  EXPECT_FALSE(tall.check(Pose::planar(0.69, 0, 0)).hit);
  EXPECT_EQ(tall.check(Pose::planar(0.71, 0, 0)).label, "table");
}

TEST(SimBodyCollision, ChairSeat) {
  const Mesh m = furnishedRoom();
  EXPECT_EQ(BodyCollider(m, rect(0.6, 0.5, 0.6)).check(Pose::planar(-1.75, 0, 0)).label, "chair");
  EXPECT_FALSE(BodyCollider(m, rect(0.6, 0.5, 0.4)).check(Pose::planar(-1.75, 0, 0)).hit);
}

TEST(SimBodyCollision, NonConvexFootprint) {
  RobotSpec l;
  l.footprint = {{0, 0}, {1, 0}, {1, 0.3}, {0.3, 0.3}, {0.3, 1}, {0, 1}};
  l.height = 1.0;
  Mesh notch, arm;
  mapgen::MeshBuilder(notch).box({0.6f, 0.6f, 0.f}, {0.7f, 0.7f, 1.f}, "post");
  mapgen::MeshBuilder(arm).box({0.6f, 0.05f, 0.f}, {0.7f, 0.15f, 1.f}, "post");
  for (int winding = 0; winding < 2; ++winding) {
    EXPECT_FALSE(BodyCollider(notch, l).check(Pose::planar(0, 0, 0)).hit);
    EXPECT_EQ(BodyCollider(arm, l).check(Pose::planar(0, 0, 0)).label, "post");
    // Turned by 90 degrees about base_link, the arm along +x now points along +y.
    EXPECT_FALSE(BodyCollider(arm, l).check(Pose::planar(0, 0, M_PI / 2)).hit);
    std::reverse(l.footprint.begin(), l.footprint.end());
  }
}

TEST(SimBodyCollision, RotationOfALongRobotNextToAWall) {
  const Mesh m = furnishedRoom();
  const BodyCollider body(m, rect(1.0, 0.2, 1.0));
  EXPECT_EQ(body.check(Pose::planar(2.8, 0, 0)).label, "wall");  // reaches to x = 3.3
  EXPECT_EQ(body.check(Pose::planar(2.8, 0, M_PI)).label, "wall");
  EXPECT_FALSE(body.check(Pose::planar(2.8, 0, M_PI / 2)).hit);  // x in [2.7, 2.9]
  EXPECT_EQ(body.check(Pose::planar(2.91, 0, M_PI / 2)).label, "wall");
  EXPECT_FALSE(body.check(Pose::planar(0, 1.7, 0)).hit);
  EXPECT_EQ(body.check(Pose::planar(0, 1.7, M_PI / 2)).label, "wall");  // y up to 2.2
}

TEST(SimBodyCollision, RoundFootprintIsA16Gon) {
  const Mesh m = furnishedRoom();
  RobotSpec r;
  r.radius = 0.25;
  r.height = 1.0;
  const BodyCollider body(m, r);
  ASSERT_EQ(body.pieces().size(), 1u);
  EXPECT_EQ(body.pieces()[0].size(), 16u);
  EXPECT_FALSE(body.check(Pose::planar(2.74, 0, 0)).hit);
  EXPECT_TRUE(body.check(Pose::planar(2.76, 0, 0)).hit);
}

TEST(SimBodyCollision, People) {
  const Mesh m = furnishedRoom();
  const BodyCollider body(m, rect(0.6, 0.5, 1.2));
  PersonSpec s;
  s.waypoints = {{0.3, 0.0}};  // standing 0.3 m in front of base_link
  const PeopleScene one = People({s}).scene(0.0, {0, 0});
  const BodyContact c = body.check(Pose::planar(0, 0, 0), &one);
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.what, "person");
  EXPECT_EQ(c.label, "person 0");
  EXPECT_EQ(c.triangle, kNoBodyTriangle);
  expectWithinBody(c, Pose::planar(0, 0, 0), 0.3, 1.2);
  EXPECT_FALSE(body.check(Pose::planar(-0.5, 0, 0), &one).hit);  // front edge at -0.2
  s.waypoints = {{2.8, 0.0}};  // by the wall
  const PeopleScene by_wall = People({s}).scene(0.0, {0, 0});
  EXPECT_EQ(body.check(Pose::planar(2.6, 0, 0), &by_wall).label, "person 0");
  EXPECT_EQ(body.check(Pose::planar(2.71, 0, 0), &by_wall).what, "map");  // the mesh comes first

  // Hand-made boxes: person 0 far away, person 1 a 0.3 m deep box with its back at x = 0.85.
  PeopleScene two;
  for (float x : {-2.5f, 1.0f}) {
    two.ranges.push_back({two.boxes.size(), two.boxes.size() + 1});
    two.boxes.push_back({Eigen::Matrix3f::Identity(), {x, 0.f, 0.9f}, {0.15f, 0.25f, 0.9f}});
    two.bounds.emplace_back(Eigen::Vector3f(x - 0.15f, -0.25f, 0.f), Eigen::Vector3f(x + 0.15f, 0.25f, 1.8f));
  }
  EXPECT_FALSE(body.check(Pose::planar(0.54, 0, 0), &two).hit);
  EXPECT_EQ(body.check(Pose::planar(0.56, 0, 0), &two).label, "person 1");
  PeopleScene bare;  // boxes only: one person
  bare.boxes = two.boxes;
  EXPECT_EQ(body.check(Pose::planar(0.56, 0, 0), &bare).label, "person 0");
}

TEST(SimBodyCollision, BroadPhaseFindsWhatBruteForceFinds) {
  const Mesh m = furnishedRoom();
  const RobotSpec spec = rect(0.6, 0.5, 1.2);
  const BodyCollider body(m, spec);
  int hits = 0, misses = 0;
  for (double x = -3.3; x <= 3.3; x += 0.173)
    for (double y = -2.3; y <= 2.3; y += 0.191) {
      const Pose p = Pose::fromXYZRPY(x, y, std::fmod(7 * x + 3 * y, 0.5) - 0.1, 0, 0, 5 * x + 11 * y);
      const BodyContact c = body.check(p);
      EXPECT_EQ(c.triangle, bruteForce(m, body, p, 0.02, spec.height)) << x << " " << y;
      EXPECT_EQ(body.check(p).triangle, c.triangle);  // deterministic
      (c.hit ? hits : misses)++;
    }
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 100);
}

TEST(SimBodyCollision, BadInputThrows) {
  const Mesh m = furnishedRoom();
  const BodyCollider body(m, rect(0.6, 0.5, 1.2));
  EXPECT_THROW(body.check(Pose::planar(NAN, 0, 0)), std::invalid_argument);
  try {
    body.check(Pose::planar(0, 2e6, 0));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2000000"), std::string::npos) << e.what();
  }
  EXPECT_THROW(BodyCollider(m, rect(0.6, 0.5, 1.2), 1.5), std::invalid_argument);
  RobotSpec flat = rect(0.6, 0.5, 1.2);
  flat.footprint = {{0, 0}, {1, 0}, {2, 0}};
  EXPECT_THROW(BodyCollider(m, flat), std::invalid_argument);
}

TEST(SimBodyCollision, FarAndBrokenTrianglesDoNotHurt) {
  Mesh m = furnishedRoom();
  const uint32_t junk = m.labelId("junk");
  m.addTriangle({1e9f, 0, 0}, {1e9f, 1, 0}, {1e9f, 0, 1}, junk);  // stretches the grid to 1e9 m
  m.addTriangle({NAN, 0, 0.5f}, {0, 0, 0.5f}, {0, 1, 0.5f}, junk);  // a broken one in the middle
  const BodyCollider body(m, rect(0.6, 0.5, 1.2));
  EXPECT_FALSE(body.check(Pose::planar(0, 0, 0)).hit);
  EXPECT_EQ(body.check(Pose::planar(2.71, 0, 0)).label, "wall");
}

}  // namespace polyloc::t_sim_body_collision
