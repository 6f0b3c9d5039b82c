#include <polyloc/sim/convex_overlap.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_convex_overlap {

using namespace polyloc;


// Unit cube [0, 1]^3 shifted by d, optionally turned about z by yaw about its centre.
ConvexShape cube(const Eigen::Vector3d& d = Eigen::Vector3d::Zero(), double yaw = 0) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return ConvexShape::box(Eigen::Vector3d(0.5, 0.5, 0.5) + d, r, Eigen::Vector3d(0.5, 0.5, 0.5));
}

double area(const std::vector<Eigen::Vector2d>& p) {
  double a = 0;
  for (size_t i = 0, n = p.size(); i < n; ++i) a += p[i].x() * p[(i + 1) % n].y() - p[(i + 1) % n].x() * p[i].y();
  return 0.5 * a;
}


TEST(SimConvexOverlap, CubesOverlapTouchOrSeparate) {
  EXPECT_TRUE(overlap(cube(), cube({0.5, 0.2, -0.3})));
  EXPECT_TRUE(overlap(cube(), cube({1.0, 0, 0})));  // a shared face: touching counts as contact
  EXPECT_TRUE(overlap(cube(), cube({1.0, 1.0, 1.0})));  // a shared corner
  EXPECT_FALSE(overlap(cube(), cube({1.001, 0, 0})));
  EXPECT_FALSE(overlap(cube(), cube({0, 0, -1.001})));
  // Turned by 45 degrees, the cube's corner reaches 0.5 sqrt(2) from its centre.
  const double reach = 0.5 + 0.5 * std::sqrt(2.0);
  EXPECT_TRUE(overlap(cube(), cube({reach - 0.001, 0, 0}, M_PI / 4)));
  EXPECT_FALSE(overlap(cube(), cube({reach + 0.001, 0, 0}, M_PI / 4)));
}

TEST(SimConvexOverlap, TriangleThroughABoxWithNoVertexInside) {
  // Vertical triangle in x = 0.5 piercing the cube: at z = 0.5 it spans y in [-0.25, 1.25].
  EXPECT_TRUE(overlap(cube(), ConvexShape::triangle({0.5, -1, -1}, {0.5, 2, -1}, {0.5, 0.5, 2})));
  // A large horizontal triangle slicing the cube.
  EXPECT_TRUE(overlap(cube(), ConvexShape::triangle({-1, -1, 0.5}, {3, -1, 0.5}, {-1, 3, 0.5})));
}

TEST(SimConvexOverlap, TriangleAboveABoxTop) {
  EXPECT_FALSE(overlap(cube(), ConvexShape::triangle({-1, -1, 1.001}, {3, -1, 1.001}, {-1, 3, 1.001})));
  EXPECT_TRUE(overlap(cube(), ConvexShape::triangle({-1, -1, 1.0}, {3, -1, 1.0}, {-1, 3, 1.0})));  // touching
}

TEST(SimConvexOverlap, EdgeAgainstEdgeNeedsTheCrossAxis) {
  // A triangle in the plane y = 0.5 whose edge x + z = c passes the cube's edge (x = 1, z = 1):
  // no face normal separates them, only the cross product of the two edges does.
  for (double c : {2.01, 1.99}) {
    const ConvexShape t = ConvexShape::triangle({c, 0.5, 0}, {0, 0.5, c}, {3, 0.5, 3});
    EXPECT_EQ(overlap(cube(), t), c < 2) << c;
  }
}

TEST(SimConvexOverlap, PrismMatchesTheBoxItExtrudes) {
  const std::vector<Eigen::Vector2d> square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const ConvexShape p = ConvexShape::prism(square, 0, 1, {0, 0}, 0);
  EXPECT_TRUE(overlap(p, cube({0.99, 0, 0})));
  EXPECT_FALSE(overlap(p, cube({1.01, 0, 0})));
  // Turned by 90 degrees about the origin, the square covers x in [-1, 0].
  const ConvexShape q = ConvexShape::prism(square, 0, 1, {0, 0}, M_PI / 2);
  EXPECT_TRUE(overlap(q, cube({-1.5, 0.2, 0})));
  EXPECT_FALSE(overlap(q, cube({0.01, 0, 0})));
}

TEST(SimConvexOverlap, ConvexPiecesOfAnLShape) {
  std::vector<Eigen::Vector2d> l{{0, 0}, {1, 0}, {1, 0.3}, {0.3, 0.3}, {0.3, 1}, {0, 1}};
  for (int winding = 0; winding < 2; ++winding) {
    const auto pieces = convexPieces(l);
    ASSERT_EQ(pieces.size(), 4u);
    double sum = 0;
    for (const auto& t : pieces) {
      EXPECT_GT(area(t), 0);  // counter-clockwise
      sum += area(t);
    }
    EXPECT_NEAR(sum, 0.3 + 0.3 * 0.7, 1e-12);
    std::reverse(l.begin(), l.end());
  }
  const std::vector<Eigen::Vector2d> square{{0, 0}, {0, 1}, {1, 1}, {1, 0}};  // clockwise
  const auto one = convexPieces(square);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(area(one[0]), 1.0, 1e-12);
  EXPECT_THROW(convexPieces({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), std::invalid_argument);  // a bow tie
  EXPECT_THROW(convexPieces({{0, 0}, {1, 0}}), std::invalid_argument);
}

}  // namespace polyloc::t_sim_convex_overlap
