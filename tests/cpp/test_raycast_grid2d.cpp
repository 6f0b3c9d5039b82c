// grid2d backend, beyond the contract of every caster (test_raycast_conformance.cpp): 3D rays
// projected onto the plane, filled or hollow solids, the grid given back and built from.
#include <polyloc/raycast/grid2d.hpp>

#include "fixtures.hpp"
#include "raycast_helpers.hpp"

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_grid2d {

using namespace polyloc;
using polyloc::test::castOne;
using polyloc::test::freeAt;
using polyloc::test::kInfRange;


// Interior [-2, 2] x [-1.5, 1.5] x [0, 3]; walls 0.2 m thick; cells of 5 cm.
struct Grid2dRoom : ::testing::Test {
  Mesh mesh = polyloc::test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  Grid2dCaster grid{mesh, Grid2dOptions{}};
  const float res = 0.05f;
};


TEST_F(Grid2dRoom, ThreeDRaysAreProjectedOntoThePlane) {
  // 45 deg up: the planar range 2 m becomes 2 / cos(45 deg); the ceiling is not in the slice.
  EXPECT_NEAR(castOne(grid, {0, 0, 0.3f}, {1, 0, 1}), 2.f * std::sqrt(2.f), res * std::sqrt(2.f));
  // Straight up: no planar motion, a miss.
  EXPECT_EQ(castOne(grid, {0, 0, 0.3f}, {0, 0, 1}), kInfRange);
}

TEST_F(Grid2dRoom, SolidsAreFilledAndClearanceHolds) {
  EXPECT_FALSE(freeAt(grid, {2.1f, 0, 0.3f}, 0.f));   // inside the wall slab
  EXPECT_TRUE(freeAt(grid, {0, 0, 0.3f}, 1.f));       // 1.5 m from every wall
  EXPECT_FALSE(freeAt(grid, {1.8f, 0, 0.3f}, 0.3f));  // 0.2 m from the wall x = 2
  EXPECT_TRUE(freeAt(grid, {1.6f, 0, 0.3f}, 0.3f));   // 0.4 m from it
  Grid2dOptions hollow;
  hollow.fill_solids = false;
  const Grid2dCaster g2(mesh, hollow);
  EXPECT_TRUE(freeAt(g2, {2.1f, 0, 0.3f}, 0.f));  // only the slice outline is occupied
}

TEST_F(Grid2dRoom, BuildsFromAMapGridAndGivesItBack) {
  const OccupancyGrid g = grid.grid();
  EXPECT_EQ(g.width, grid.width());
  const Grid2dCaster again(g);
  const Eigen::Vector3f o(0.1f, 0.05f, 0.f);
  EXPECT_FLOAT_EQ(castOne(again, o, {1, 0, 0}), castOne(grid, o, {1, 0, 0}));
  OccupancyGrid rotated = g;
  rotated.origin_yaw = 0.1;
  EXPECT_THROW(Grid2dCaster{rotated}, std::invalid_argument);
}

}  // namespace polyloc::t_raycast_grid2d
