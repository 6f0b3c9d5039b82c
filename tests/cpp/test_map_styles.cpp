// The map builds of the real-log robustness matrix: grid closing and dilation (OpenCV), a mesh
// warped by a smooth displacement field, end-point maps whose hits stick.
#include <polyloc/map/extrude.hpp>
#include <polyloc/map/grid_morphology.hpp>
#include <polyloc/map/mesh_warp.hpp>
#include <polyloc/map/scan_mapper.hpp>
#include <polyloc/raycast/embree.hpp>

#include "raycast_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace polyloc::t_map_styles {  // the file's own: the suite is compiled in batches (unity build)
namespace {

OccupancyGrid emptyGrid(size_t w, size_t h) {
  OccupancyGrid g;
  g.resize(w, h, OccupancyGrid::kFree);
  return g;
}

size_t occupiedCount(const OccupancyGrid& g) {
  size_t n = 0;
  for (int8_t c : g.cells) n += c == OccupancyGrid::kOccupied;
  return n;
}

TEST(GridMorphology, ClosingBridgesOneCellGapsAndKeepsEveryWallCell) {
  OccupancyGrid g = emptyGrid(20, 10);
  for (size_t x = 2; x < 18; x += 2) g.at(x, 5) = OccupancyGrid::kOccupied;  // a wall seen every other cell
  g.at(0, 0) = OccupancyGrid::kUnknown;
  const OccupancyGrid c = closeOccupied(g, 3);
  for (size_t x = 2; x <= 16; ++x) EXPECT_TRUE(c.occupied(x, 5)) << x;
  EXPECT_FALSE(c.occupied(1, 5));
  EXPECT_FALSE(c.occupied(17, 5));
  EXPECT_FALSE(c.occupied(9, 4));   // the wall does not get thicker
  EXPECT_EQ(occupiedCount(c), 15u);
  EXPECT_EQ(c.at(0, 0), OccupancyGrid::kUnknown);
  EXPECT_THROW(closeOccupied(g, 2), std::invalid_argument);
  EXPECT_THROW(closeOccupied(g, 0), std::invalid_argument);
}

TEST(GridMorphology, DilationThickensEveryWallByACell) {
  OccupancyGrid g = emptyGrid(10, 10);
  for (size_t x = 2; x < 8; ++x) g.at(x, 5) = OccupancyGrid::kOccupied;
  const OccupancyGrid d = dilateOccupied(g, 1);
  EXPECT_EQ(occupiedCount(d), 8u * 3u);
  EXPECT_TRUE(d.occupied(1, 4) && d.occupied(8, 6));
  EXPECT_FALSE(d.occupied(5, 7));
  EXPECT_EQ(occupiedCount(dilateOccupied(g, 0)), 6u);
}

TEST(MeshWarp, DisplacesSmoothlyWithTheGivenSpread) {
  const MeshWarpOptions o{0.02, 0.5, 7};
  // Over many points the std of each component is sigma (the normalised bilinear mix).
  double s2 = 0;
  size_t n = 0;
  for (double x = -20; x < 20; x += 0.37)
    for (double y = -20; y < 20; y += 0.41) {
      const Eigen::Vector2d d = warpDisplacement(x, y, o);
      s2 += d.squaredNorm(), n += 2;
    }
  EXPECT_NEAR(std::sqrt(s2 / double(n)), 0.02, 0.002);
  // Smooth: points 1 mm apart move alike (to a fraction of a millimetre).
  for (double x = -3; x < 3; x += 0.13) {
    EXPECT_LT((warpDisplacement(x, 1.0, o) - warpDisplacement(x + 0.001, 1.0, o)).norm(), 5e-4) << x;
  }
  EXPECT_EQ(warpDisplacement(1.2, 3.4, o), warpDisplacement(1.2, 3.4, o));
  EXPECT_NE(warpDisplacement(1.2, 3.4, o), warpDisplacement(1.2, 3.4, {0.02, 0.5, 8}));
  EXPECT_THROW(warpDisplacement(0, 0, {0.02, 0.0, 1}), std::invalid_argument);
  EXPECT_THROW(warpDisplacement(0, 0, {-1, 0.5, 1}), std::invalid_argument);
}

TEST(MeshWarp, AWarpedWallMovesByCentimetresAndStaysClosed) {
  OccupancyGrid g = emptyGrid(200, 40);
  g.resolution = 0.05;
  for (size_t x = 0; x < 200; ++x) g.at(x, 20) = OccupancyGrid::kOccupied;  // a 10 m wall at y = 1.0..1.05
  const Mesh straight = extrudeGrid(g);
  const Mesh warped = warpMesh(straight, {0.02, 0.5, 3});
  ASSERT_EQ(warped.numTriangles(), straight.numTriangles());
  const EmbreeCaster caster(warped);
  // Rays up the y axis from y = 0 at 0.5 m height: the wall's near face at 1.0 m +- centimetres.
  double sum2 = 0, worst = 0;
  size_t n = 0;
  for (double x = 0.3; x < 9.7; x += 0.1) {
    const float r = test::castOne(caster, {float(x), 0.f, 0.5f}, Eigen::Vector3f::UnitY(), 0.f, 5.f);
    ASSERT_TRUE(std::isfinite(r)) << "a ray slipped through at x = " << x;
    sum2 += (r - 1.0) * (r - 1.0), worst = std::max(worst, std::abs(r - 1.0)), ++n;
  }
  EXPECT_GT(std::sqrt(sum2 / double(n)), 0.008);
  EXPECT_LT(worst, 0.1);
}

TEST(ScanMapper, StickyHitsKeepEveryEndPointCell) {
  // A wall at x = 2.02 seen head on, then grazed by beams that cross its cells: with log-odds the
  // grazing beams clear some of them, sticky hits keep them.
  ScanMapperConfig c;
  c.hit_beyond = 0;
  c.sticky_hits = true;
  ScanMapper m(c);
  std::vector<float> head(1, 2.02f);
  ASSERT_EQ(m.add(0, 0, 0, head.data(), 1, 0, 0.01, 0, 30), ScanMapper::Added::Used);
  std::vector<float> through(1, 5.0f);  // a later beam ends beyond: it crosses the hit cell
  for (int k = 0; k < 20; ++k) m.add(0, 0, 0, through.data(), 1, 0, 0.01, 0, 30);
  const OccupancyGrid g = m.grid();
  const size_t x = size_t(std::floor((2.02 - g.origin_x) / g.resolution)), y = size_t(std::floor((0.0 - g.origin_y) / g.resolution));
  EXPECT_TRUE(g.occupied(x, y));
  c.sticky_hits = false;
  ScanMapper plain(c);
  plain.add(0, 0, 0, head.data(), 1, 0, 0.01, 0, 30);
  for (int k = 0; k < 20; ++k) plain.add(0, 0, 0, through.data(), 1, 0, 0.01, 0, 30);
  EXPECT_FALSE(plain.grid().occupied(x, y));
}

}  // namespace
}  // namespace polyloc
