// Grid -> 3D map extrusion: closed, outward-facing output that survives OBJ, merged boxes, and
// ranges in the extruded map (Embree) that match the grid's own (grid2d) within a cell.
#include <polyloc/map/extrude.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/grid2d.hpp>
#include <polyloc/raycast/workload.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_map_extrude {

using namespace polyloc;
using polyloc::test::TempDir;


// A 60 x 40 grid of 5 cm (3 x 2 m): an outer wall, an inner wall with a door gap, a pillar.
OccupancyGrid rooms() {
  OccupancyGrid g;
  g.resize(60, 40, OccupancyGrid::kFree);
  g.resolution = 0.05;
  g.origin_x = -1.0, g.origin_y = -0.5;
  for (size_t x = 0; x < 60; ++x) g.at(x, 0) = g.at(x, 39) = OccupancyGrid::kOccupied;
  for (size_t y = 0; y < 40; ++y) g.at(0, y) = g.at(59, y) = OccupancyGrid::kOccupied;
  for (size_t y = 0; y < 40; ++y)
    if (y < 15 || y > 22) g.at(30, y) = g.at(31, y) = OccupancyGrid::kOccupied;
  for (size_t x = 45; x < 48; ++x)
    for (size_t y = 10; y < 13; ++y) g.at(x, y) = OccupancyGrid::kOccupied;
  return g;
}


TEST(MapExtrude, ClosedOutwardAndMerged) {
  const OccupancyGrid g = rooms();
  ExtrudeStats st;
  const Mesh m = extrudeGrid(g, {}, &st);
  const ValidationReport r = validateMesh(m);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.consistentWinding());
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_LT(st.boxes, 20u);  // a few boxes, not one per occupied cell
  EXPECT_EQ(m.numTriangles(), 12 * (st.boxes + 1));
  ExtrudeOptions per_cell;
  per_cell.merge = false;
  ExtrudeStats st2;
  extrudeGrid(g, per_cell, &st2);
  EXPECT_EQ(st2.boxes, st.occupied_cells);
  // Through an OBJ file (vertices welded by position): still closed.
  TempDir dir;
  saveMesh(m, dir.file("x.obj"));
  const ValidationReport r2 = validateMesh(loadMesh(dir.file("x.obj")));
  EXPECT_TRUE(r2.closed()) << r2.summary();
  EXPECT_TRUE(r2.consistentWinding());
  EXPECT_THROW(extrudeGrid(g, ExtrudeOptions{-1.0}), std::invalid_argument);
}

TEST(MapExtrude, RangesInTheExtrudedMapMatchTheGrid) {
  TempDir dir;
  saveGridMap(rooms(), dir.file("rooms.yaml"));  // through PGM + YAML, as the CLI reads it
  const OccupancyGrid g = loadGridMap(dir.file("rooms.yaml"));
  ExtrudeOptions o;
  o.height = 2.0;
  const Mesh m = extrudeGrid(g, o);
  EXPECT_NEAR(m.bounds().max().z(), 2.0f, 1e-5f);
  const EmbreeCaster mesh_caster(m);
  const Grid2dCaster grid_caster(g);
  // Scans at 0.3 m from free cells of both rooms.
  std::vector<Pose> poses;
  for (double x : {-0.6, 0.0, 0.9, 1.5})
    for (double y : {-0.2, 0.5, 1.1}) poses.push_back(Pose::fromXYZRPY(x, y, 0.3, 0, 0, 0.1));
  const BeamSet beams = horizontalFan(72, 10.f);
  std::vector<float> a(poses.size() * beams.size()), b(a.size());
  mesh_caster.castScans(poses, beams, {a.data()});
  grid_caster.castScans(poses, beams, {b.data()});
  size_t within = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(std::isfinite(a[i]) && std::isfinite(b[i])) << i;  // closed rooms: all hit
    within += std::abs(a[i] - b[i]) <= 0.05f * std::sqrt(2.f) + 1e-3f;
  }
  // Measured 96.9 %: the rest graze wall ends and the door gap's edges.
  EXPECT_GE(double(within) / double(a.size()), 0.95);
}

}  // namespace polyloc::t_map_extrude
