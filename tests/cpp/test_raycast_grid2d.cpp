// grid2d backend: the box room gives known ranges within a cell; windows, 3D rays projected onto
// the plane, filled solids, clearance; agreement with Embree on the lab map.
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/grid2d.hpp>

#include "fixtures.hpp"
#include "raycast_helpers.hpp"

#include <gtest/gtest.h>

using namespace polyloc;
using polyloc::test::castOne;
using polyloc::test::freeAt;
using polyloc::test::kInfRange;

namespace {

// Interior [-2, 2] x [-1.5, 1.5] x [0, 3]; walls 0.2 m thick; cells of 5 cm.
struct Grid2dRoom : ::testing::Test {
  Mesh mesh = polyloc::test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  Grid2dCaster grid{mesh, Grid2dOptions{}};
  const float res = 0.05f;
};

}  // namespace

TEST_F(Grid2dRoom, RangesFromTheCentreWithinACell) {
  const Eigen::Vector3f o(0.1f, 0.05f, 0.3f);
  EXPECT_NEAR(castOne(grid, o, {1, 0, 0}), 1.9f, res + 1e-3f);  // a wall on a cell edge: either cell
  EXPECT_NEAR(castOne(grid, o, {-1, 0, 0}), 2.1f, res + 1e-3f);
  EXPECT_NEAR(castOne(grid, o, {0, 1, 0}), 1.45f, res + 1e-3f);
  EXPECT_NEAR(castOne(grid, o, {0, -1, 0}), 1.55f, res + 1e-3f);
  // Oblique: the wall x = 2 at 30 deg.
  const float c = std::cos(0.5236f), s = std::sin(0.5236f);
  EXPECT_NEAR(castOne(grid, o, {c, s, 0}), 1.9f / c, 1.5f * res);
  // Scans give the same as rays.
  const BeamSet beams = horizontalFan(4, 30.f);
  const Pose pose = Pose::fromXYZRPY(0.1, 0.05, 0.3, 0, 0, 0);
  float r[4];
  grid.castScans(std::span<const Pose>(&pose, 1), beams, {r});
  EXPECT_NEAR(r[0], 1.9f, res + 1e-3f);
  EXPECT_NEAR(r[1], 1.45f, res + 1e-3f);
}

TEST_F(Grid2dRoom, ThreeDRaysAreProjectedOntoThePlane) {
  // 45 deg up: the planar range 2 m becomes 2 / cos(45 deg); the ceiling is not in the slice.
  EXPECT_NEAR(castOne(grid, {0, 0, 0.3f}, {1, 0, 1}), 2.f * std::sqrt(2.f), res * std::sqrt(2.f));
  // Straight up: no planar motion, a miss.
  EXPECT_EQ(castOne(grid, {0, 0, 0.3f}, {0, 0, 1}), kInfRange);
}

TEST_F(Grid2dRoom, WindowsAndMisses) {
  const Eigen::Vector3f o(0, 0, 0.3f);
  EXPECT_EQ(castOne(grid, o, {1, 0, 0}, 0.f, 1.f), kInfRange);  // wall beyond tmax
  EXPECT_EQ(castOne(grid, o, {1, 0, 0}, 1.5f, 1.f), kInfRange);  // empty window
  // tmin inside the wall: the ray starts in solid, range = tmin (backface_is_solid).
  EXPECT_NEAR(castOne(grid, o, {1, 0, 0}, 2.1f, 10.f), 2.1f, 1e-5f);
  // Beyond the wall: nothing more to hit.
  EXPECT_EQ(castOne(grid, o, {1, 0, 0}, 2.5f, 10.f), kInfRange);
  grid.options.miss_is_max_range = true;
  EXPECT_FLOAT_EQ(castOne(grid, o, {1, 0, 0}, 0.f, 1.f), 1.f);
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

TEST(Grid2dLab, AgreesWithEmbreeWithinTheResolution) {
  const Mesh mesh = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  const Grid2dCaster grid(mesh);
  const auto a = polyloc::test::agreeWithEmbree(grid, mesh, 200, 90, 0.3);
  // Measured (5 cm cells): median 2.6 cm, p75 3.9 cm, hit/miss differs on 1.5 % (grazing beams,
  // thin parts like chair legs that a 5 cm slice rasterises wider or narrower).
  EXPECT_GT(a.both_hit, 5000u);
  EXPECT_LT(a.median, 0.05);
  EXPECT_LT(a.p75, 0.075);
  EXPECT_LT(a.hit_disagreement, 0.03);
}
