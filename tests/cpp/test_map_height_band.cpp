// The map's free space sliced over the robot's height (map/height_band.hpp): known geometry built
// here (table top, low box, lamp, wall, ramp, hole, platform, danger), bad options, the same grid
// for any thread count, and the bundled lab map (doors, tables, ramp, platform, stairwell).
#include <polyloc/map/height_band.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mapgen/lab.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_map_height_band {

using namespace polyloc;
using V3 = Eigen::Vector3f;
using V3d = Eigen::Vector3d;


constexpr int8_t kFree = OccupancyGrid::kFree, kOcc = OccupancyGrid::kOccupied, kUnknown = OccupancyGrid::kUnknown;

// A floor slab 4 x 4 m, top at z = 0.
Mesh floorSlab() {
  Mesh m;
  m.source = "test floor";
  m.addBox({0, 0, -0.1}, {4, 4, 0}, m.labelId("floor"));
  return m;
}

size_t cellIndex(const HeightBand& b, double x, double y) {
  const OccupancyGrid& g = b.grid;
  const double fx = std::floor((x - g.origin_x) / g.resolution), fy = std::floor((y - g.origin_y) / g.resolution);
  EXPECT_TRUE(fx >= 0 && fy >= 0 && fx < double(g.width) && fy < double(g.height)) << x << ", " << y;
  return size_t(fy) * g.width + size_t(fx);
}
int8_t cell(const HeightBand& b, double x, double y) { return b.grid.cells[cellIndex(b, x, y)]; }
float floorAt(const HeightBand& b, double x, double y) { return b.floor_z[cellIndex(b, x, y)]; }
bool danger(const HeightBand& b, double x, double y) { return b.danger[cellIndex(b, x, y)] != 0; }

HeightBandOptions withHeight(double h) {
  HeightBandOptions o;
  o.height = h;
  return o;
}

// A wedge over [x0, x1] x [y0, y1] rising along +x from z = 0 to rise, closed and outward.
void addRamp(Mesh& m, float x0, float x1, float y0, float y1, float rise, uint32_t label) {
  const V3 a(x0, y0, 0), b(x1, y0, 0), c(x1, y1, 0), d(x0, y1, 0), bt(x1, y0, rise), ct(x1, y1, rise);
  m.addQuad(a, bt, ct, d, label);  // top, facing up
  m.addQuad(a, d, c, b, label);    // bottom, facing down
  m.addQuad(b, c, ct, bt, label);  // high end, +x
  m.addTriangle(a, b, bt, label);  // side y0, -y
  m.addTriangle(d, ct, c, label);  // side y1, +y
}


TEST(HeightBand, TableTopOccupiedForATallRobotFreeForAShortOne) {
  Mesh m = floorSlab();
  m.addBox({1, 1, 0.70}, {2, 2, 0.73}, m.labelId("table"));
  HeightBandStats st;
  const HeightBand tall = heightBandGrid(m, withHeight(1.2), &st);
  EXPECT_EQ(tall.grid.resolution, 0.05);
  EXPECT_EQ(tall.grid.cells.size(), tall.grid.width * tall.grid.height);
  EXPECT_EQ(tall.danger.size(), tall.grid.cells.size());
  EXPECT_EQ(tall.floor_z.size(), tall.grid.cells.size());
  for (double x = 1.025; x < 2; x += 0.05)
    for (double y = 1.025; y < 2; y += 0.05) ASSERT_EQ(cell(tall, x, y), kOcc) << x << ", " << y;
  EXPECT_EQ(cell(tall, 3, 3), kFree);
  EXPECT_EQ(cell(tall, 0.9, 1.5), kFree);  // two cells beside the top's edge
  EXPECT_EQ(cell(tall, 2.1, 1.5), kFree);
  EXPECT_FLOAT_EQ(floorAt(tall, 3, 3), 0.f);
  EXPECT_EQ(st.triangles, 24u);
  EXPECT_EQ(st.floor_triangles, 2u);  // the slab's top; its bottom and sides are not walkable
  EXPECT_EQ(st.cells_occupied + st.cells_free + st.cells_unknown, tall.grid.cells.size());
  EXPECT_EQ(st.open_columns, 0u);
  const HeightBand short_robot = heightBandGrid(m, withHeight(0.6));
  EXPECT_EQ(cell(short_robot, 1.5, 1.5), kFree);
  EXPECT_EQ(cell(short_robot, 1.025, 1.975), kFree);
}

TEST(HeightBand, BelowClearanceAndAboveTheRobotAreFree) {
  Mesh m = floorSlab();
  m.addBox({0.5, 0.5, 0}, {1.0, 1.0, 0.03}, m.labelId("box"));        // a cable duct, 3 cm
  m.addBox({2.5, 2.5, 2.0}, {3.0, 3.0, 2.1}, m.labelId("lamp"));      // a lamp at 2 m
  // An open lone quad (one face, no solid) at 2 m: no solid to fill the space below it.
  m.addQuad({1.5f, 2.5f, 2.f}, {2.f, 2.5f, 2.f}, {2.f, 3.f, 2.f}, {1.5f, 3.f, 2.f}, m.labelId("lamp"));
  m.addBox({3.0, 0.5, 0}, {3.5, 1.0, 0.08}, m.labelId("box"));        // 8 cm: above the clearance
  HeightBandStats st;
  const HeightBand b = heightBandGrid(m, {}, &st);
  EXPECT_EQ(cell(b, 0.75, 0.75), kFree);
  EXPECT_EQ(cell(b, 2.75, 2.75), kFree);
  EXPECT_EQ(cell(b, 1.75, 2.75), kFree);
  EXPECT_GT(st.open_columns, 0u);  // under the lone quad
  EXPECT_EQ(cell(b, 3.25, 0.75), kOcc);
  HeightBandOptions low;
  low.clearance = 0.02;
  EXPECT_EQ(cell(heightBandGrid(m, low), 0.75, 0.75), kOcc);
  HeightBandOptions tall;
  tall.height = 2.05;
  EXPECT_EQ(cell(heightBandGrid(m, tall), 2.75, 2.75), kOcc);
}

TEST(HeightBand, WallOccupiesTheCellsItStandsOn) {
  Mesh m = floorSlab();
  m.addBox({1.93, 0, 0}, {2.27, 4, 2.5}, m.labelId("wall"));  // 34 cm thick: cells inside it see no face
  HeightBandStats st;
  const HeightBand b = heightBandGrid(m, {}, &st);
  EXPECT_GT(st.cells_in_solid, 0u);
  const double r = b.grid.resolution;
  for (size_t j = 0; j < b.grid.height; ++j) {
    const double y = b.grid.origin_y + (double(j) + 0.5) * r;
    if (y < 0.1 || y > 3.9) continue;
    for (size_t i = 0; i < b.grid.width; ++i) {
      const double x = b.grid.origin_x + (double(i) + 0.5) * r;
      if (x < 0.1 || x > 3.9) continue;
      const bool on = x > 1.93 - 0.5 * r && x < 2.27 + 0.5 * r;  // the cell's square overlaps the wall
      ASSERT_EQ(b.grid.at(i, j), on ? kOcc : kFree) << x << ", " << y;
    }
  }
}

TEST(HeightBand, BandFollowsTheLocalFloorUpARamp) {
  Mesh m = floorSlab();
  addRamp(m, 1.0, 4.0, 1.0, 3.0, 0.3f, m.labelId("ramp"));  // 0.1 m per m: 5.7 deg
  m.addBox({1.2, 2.0, 1.30}, {1.3, 2.1, 1.35}, m.labelId("beam"));  // floor ~0.02: above 1.22
  m.addBox({3.6, 2.0, 1.30}, {3.7, 2.1, 1.35}, m.labelId("beam"));  // floor ~0.265: in the band
  m.addBox({3.0, 1.6, 0.2}, {3.1, 1.7, 0.24}, m.labelId("box"));    // 4 cm on the ramp (0.2 there): floor
  m.addBox({2.0, 1.6, 0.1}, {2.1, 1.7, 0.3}, m.labelId("box"));     // 20 cm on the ramp
  HeightBandStats st;
  const HeightBand b = heightBandGrid(m, {}, &st);
  EXPECT_NEAR(floorAt(b, 2.525, 2.0), 0.1525, 1e-5);
  EXPECT_NEAR(floorAt(b, 0.5, 2.0), 0.0, 1e-6);
  EXPECT_EQ(cell(b, 2.5, 2.0), kFree);
  EXPECT_EQ(cell(b, 1.25, 2.05), kFree);
  EXPECT_EQ(cell(b, 3.65, 2.05), kOcc);
  EXPECT_EQ(cell(b, 3.05, 1.65), kFree);
  EXPECT_EQ(cell(b, 2.05, 1.65), kOcc);
  // The ramp's sides: once higher than the clearance, a drop seen from the ramp and a step
  // seen from beside it; near its foot the side is lower than the clearance.
  EXPECT_EQ(cell(b, 3.525, 1.025), kOcc);  // on the ramp beside its edge: a drop of 0.25 m
  EXPECT_EQ(cell(b, 2.025, 2.975), kOcc);
  EXPECT_EQ(cell(b, 3.525, 0.925), kFree);  // one cell away from the side
  EXPECT_EQ(cell(b, 3.5, 1.125), kFree);
  EXPECT_EQ(cell(b, 1.2, 0.975), kFree);
  EXPECT_EQ(cell(b, 1.2, 1.025), kFree);
  EXPECT_EQ(cell(b, 0.9, 2.0), kFree);  // the foot of the ramp is flush with the floor
  // The same ramp steeper than the limit is no floor but an obstacle.
  HeightBandOptions flat;
  flat.max_floor_slope_deg = 5;
  EXPECT_EQ(cell(heightBandGrid(m, flat), 2.5, 2.0), kOcc);
}

TEST(HeightBand, PlatformEdgeIsMarkedOnOneSideAtLeast) {
  Mesh m = floorSlab();
  // Edges off and on cell boundaries: the face falls in the low cell (south), the high cell (west,
  // east) or on the boundary (north).
  m.addBox({1.01, 0.99, 0}, {2.98, 3.0, 0.3}, m.labelId("floor"));
  m.addBox({0.2, 3.2, 0}, {0.8, 3.8, 0.03}, m.labelId("floor"));  // a 3 cm step: driven over
  HeightBandStats st;
  const HeightBand b = heightBandGrid(m, {}, &st);
  EXPECT_NEAR(floorAt(b, 2.0, 2.0), 0.3, 1e-6);
  EXPECT_EQ(cell(b, 2.0, 2.0), kFree);
  EXPECT_EQ(cell(b, 0.5, 3.5), kFree);
  EXPECT_EQ(cell(b, 0.225, 3.5), kFree);
  const auto marked = [&](double x, double y, bool along_x) {  // the two cells either side of the edge
    return along_x ? cell(b, x - 0.03, y) == kOcc || cell(b, x + 0.03, y) == kOcc
                   : cell(b, x, y - 0.03) == kOcc || cell(b, x, y + 0.03) == kOcc;
  };
  for (double t = 1.2; t < 2.8; t += 0.1) {
    EXPECT_TRUE(marked(1.01, t, true)) << "west " << t;
    EXPECT_TRUE(marked(2.98, t, true)) << "east " << t;
    EXPECT_TRUE(marked(t, 0.99, false)) << "south " << t;
    EXPECT_TRUE(marked(t, 3.0, false)) << "north " << t;
  }
  EXPECT_GT(st.cells_drop, 0u);
  EXPECT_EQ(cell(b, 1.125, 2.0), kFree);
  EXPECT_EQ(cell(b, 0.875, 2.0), kFree);
}

TEST(HeightBand, HoleInTheFloorIsOccupiedAndBeyondTheMapUnknown) {
  Mesh m;
  m.source = "slab with a hole";
  const uint32_t floor = m.labelId("floor");
  // Four slabs around a hole [1.5, 2.5] x [1.5, 2.5]; abutting faces inside the slab.
  m.addBox({0, 0, -0.2}, {4, 1.5, 0}, floor);
  m.addBox({0, 2.5, -0.2}, {4, 4, 0}, floor);
  m.addBox({0, 1.5, -0.2}, {1.5, 2.5, 0}, floor);
  m.addBox({2.5, 1.5, -0.2}, {4, 2.5, 0}, floor);
  HeightBandStats st;
  const HeightBand b = heightBandGrid(m, {}, &st);
  for (double x = 1.525; x < 2.5; x += 0.05)
    for (double y = 1.525; y < 2.5; y += 0.05) ASSERT_EQ(cell(b, x, y), kOcc) << x << ", " << y;
  EXPECT_TRUE(std::isnan(floorAt(b, 2.0, 2.0)));
  EXPECT_EQ(cell(b, 1.3, 2.0), kFree);
  EXPECT_EQ(cell(b, 2.0, 1.3), kFree);
  EXPECT_EQ(cell(b, 2.0, 0.5), kFree);  // the seams of the slabs are no step
  EXPECT_EQ(cell(b, 0.75, 1.5), kFree);
  EXPECT_EQ(st.cells_no_floor, 400u + st.cells_unknown);
  // The padding (0.5 m) around the mesh: unknown.
  EXPECT_NEAR(b.grid.origin_x, -0.5, 1e-9);
  EXPECT_NEAR(b.grid.origin_y, -0.5, 1e-9);
  EXPECT_EQ(b.grid.width, 100u);
  EXPECT_EQ(cell(b, -0.25, 2.0), kUnknown);
  EXPECT_EQ(cell(b, 4.25, 4.25), kUnknown);
  EXPECT_EQ(st.cells_unknown, 100u * 100u - 80u * 80u);
}

TEST(HeightBand, DangerLabelsGoToTheMask) {
  Mesh m = floorSlab();
  m.addBox({1.0, 1.0, 0}, {1.04, 3.0, 1.0}, m.labelId("danger"));      // a railing post row
  m.addBox({2.5, 2.5, -3.0}, {3.5, 3.5, -2.8}, m.labelId("danger"));   // a landing under the floor
  HeightBandStats st;
  const HeightBand b = heightBandGrid(m, {}, &st);
  EXPECT_TRUE(danger(b, 1.02, 2.0));
  EXPECT_EQ(cell(b, 1.02, 2.0), kOcc);
  EXPECT_TRUE(danger(b, 3.0, 3.0));   // projected whatever its height
  EXPECT_EQ(cell(b, 3.0, 3.0), kFree);  // but no obstacle for the robot on the floor above it
  EXPECT_FALSE(danger(b, 2.0, 2.0));
  EXPECT_FALSE(danger(b, 0.5, 0.5));
  EXPECT_EQ(st.danger_triangles, 24u);
  EXPECT_GE(st.cells_danger, 400u + 40u);
  EXPECT_LE(st.cells_danger, 22u * 22u + 3u * 42u);
  HeightBandOptions none;
  none.danger_labels = {};
  HeightBandStats st2;
  heightBandGrid(m, none, &st2);
  EXPECT_EQ(st2.cells_danger, 0u);
}

TEST(HeightBand, BadOptionsNameTheOptionAndValue) {
  const Mesh m = floorSlab();
  const auto message = [&](const HeightBandOptions& o) -> std::string {
    try {
      heightBandGrid(m, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  HeightBandOptions o;
  o.resolution = 0;
  EXPECT_NE(message(o).find("resolution = 0"), std::string::npos) << message(o);
  o.resolution = 2;
  EXPECT_NE(message(o).find("resolution = 2"), std::string::npos) << message(o);
  o.resolution = -0.1;
  EXPECT_NE(message(o).find("resolution = -0.1"), std::string::npos) << message(o);
  o.resolution = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(o).find("resolution = nan"), std::string::npos) << message(o);
  o = {};
  o.height = 0.05;
  EXPECT_NE(message(o).find("height = 0.05"), std::string::npos) << message(o);
  EXPECT_NE(message(o).find("clearance"), std::string::npos) << message(o);
  o = {};
  o.clearance = -0.01;
  EXPECT_NE(message(o).find("clearance = -0.01"), std::string::npos) << message(o);
  o = {};
  o.height = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(o).find("height = inf"), std::string::npos) << message(o);
  o = {};
  o.max_floor_slope_deg = 90;
  EXPECT_NE(message(o).find("max_floor_slope_deg = 90"), std::string::npos) << message(o);
  o = {};
  o.padding = -1;
  EXPECT_NE(message(o).find("padding = -1"), std::string::npos) << message(o);
  o = {};
  o.floor_labels = {};
  EXPECT_NE(message(o).find("floor_labels"), std::string::npos) << message(o);
}

TEST(HeightBand, MeshWithoutFloorAndHugeGridAreErrors) {
  Mesh walls;
  walls.source = "walls.obj";
  walls.addBox({0, 0, 0}, {4, 0.2, 2.5}, walls.labelId("wall"));
  walls.addBox({0, 0, 0}, {0.2, 4, 2.5}, walls.labelId("Boden"));
  try {
    heightBandGrid(walls);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("walls.obj"), std::string::npos) << w;
    EXPECT_NE(w.find("floor, ramp"), std::string::npos) << w;   // what was looked for
    EXPECT_NE(w.find("wall (12)"), std::string::npos) << w;     // what the mesh has
    EXPECT_NE(w.find("Boden (12)"), std::string::npos) << w;
  }
  HeightBandOptions boden;
  boden.floor_labels = {"Boden"};
  EXPECT_NO_THROW(heightBandGrid(walls, boden));  // the labels are the caller's to choose
  Mesh big;
  big.addBox({0, 0, -0.1}, {1500, 10, 0}, big.labelId("floor"));
  try {
    heightBandGrid(big);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("30020 x 220 cells"), std::string::npos) << w;
    EXPECT_NE(w.find("20000"), std::string::npos) << w;
  }
  HeightBandOptions coarse;
  coarse.resolution = 0.1;
  EXPECT_EQ(heightBandGrid(big, coarse).grid.width, 15010u);
}

TEST(HeightBand, SameGridForAnyThreadCount) {
  Mesh m = floorSlab();
  m.addBox({1, 1, 0.70}, {2, 2, 0.73}, m.labelId("table"));
  addRamp(m, 2.2, 3.9, 0.2, 3.8, 0.2f, m.labelId("ramp"));
  m.addBox({0.3, 3.0, 0}, {0.5, 3.9, 1.0}, m.labelId("danger"));
  const HeightBand many = heightBandGrid(m);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const HeightBand single = heightBandGrid(m);
  EXPECT_EQ(many.grid.cells, single.grid.cells);
  EXPECT_EQ(many.danger, single.danger);
  for (size_t k = 0; k < many.floor_z.size(); ++k)
    ASSERT_TRUE(many.floor_z[k] == single.floor_z[k] || (std::isnan(many.floor_z[k]) && std::isnan(single.floor_z[k]))) << k;
}

// The bundled lab (maps/lab.obj) with the lab config's robot: 1.2 m, clearance 0.06.
TEST(HeightBand, LabDoorsTablesRampPlatformAndStairwell) {
  const Mesh lab = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  MapLayout layout;
  generateLab({}, &layout);
  HeightBandStats st;
  const HeightBand b = heightBandGrid(lab, {}, &st);
  EXPECT_EQ(st.open_columns, 0u);  // the lab is closed
  // Doors at x = 5.0, 8.0, 17.5 on the corridor wall y = 3.5, 0.75 m wide: free through the
  // wall at their centre (the 2 x 2 cells around it and a line across the wall).
  ASSERT_EQ(layout.doors.size(), 4u);
  for (double x : {5.0, 8.0, 17.5}) {
    for (double dx : {-0.025, 0.025})
      for (double y = 3.2; y <= 3.8; y += 0.05) EXPECT_EQ(cell(b, x + dx, y), kFree) << "door at x = " << x << ", y = " << y;
    EXPECT_EQ(cell(b, x - 0.6, 3.5), kOcc) << "wall beside the door at " << x;
    EXPECT_EQ(cell(b, x + 0.6, 3.5), kOcc) << "wall beside the door at " << x;
  }
  // Every table top (0.75 m) is under the robot's top: occupied at its centre.
  ASSERT_GE(layout.tables.size(), 10u);
  for (const auto& t : layout.tables) EXPECT_EQ(cell(b, t.x(), t.y()), kOcc) << "table at " << t.transpose();
  // Chair seats (0.45 m) too.
  for (const auto& c : layout.chairs) EXPECT_EQ(cell(b, c.x(), c.y()), kOcc) << "chair at " << c.transpose();
  // Corridor and room centres free, on the floor.
  EXPECT_EQ(cell(b, 10.0, 1.5), kFree);
  EXPECT_FLOAT_EQ(floorAt(b, 10.0, 1.5), 0.f);
  // The ramp (rising north onto the platform): free along its middle, the floor follows it.
  ASSERT_EQ(layout.ramps.size(), 1u);
  const Eigen::AlignedBox2f ramp = layout.ramps[0];
  const double rx = ramp.center().x();
  for (double y = ramp.min().y() + 0.1; y < ramp.max().y() - 0.1; y += 0.25) {
    EXPECT_EQ(cell(b, rx, y), kFree) << "ramp at y = " << y;
    EXPECT_NEAR(floorAt(b, rx, y), 0.3 * (y - ramp.min().y()) / ramp.sizes().y(), 0.01) << y;
  }
  // Its sides, higher than the clearance, are marked (from the top or from beside).
  const double side_y = ramp.max().y() - 1.0;
  EXPECT_TRUE(cell(b, ramp.min().x() - 0.025, side_y) == kOcc || cell(b, ramp.min().x() + 0.025, side_y) == kOcc);
  EXPECT_TRUE(cell(b, ramp.max().x() - 0.025, side_y) == kOcc || cell(b, ramp.max().x() + 0.025, side_y) == kOcc);
  // The platform: floor at 0.3, free on top, its edge marked outside the ramp.
  EXPECT_NEAR(floorAt(b, 23.0, 11.2), 0.3, 1e-5);
  EXPECT_EQ(cell(b, 23.0, 11.2), kFree);
  EXPECT_EQ(cell(b, rx, 10.6), kFree);  // off the ramp onto the platform
  EXPECT_TRUE(cell(b, 20.0, 10.475) == kOcc || cell(b, 20.0, 10.525) == kOcc);
  // The stairwell: no floor, occupied, and danger all over the opening.
  ASSERT_EQ(layout.stairwells.size(), 1u);
  const Eigen::AlignedBox2f hole = layout.stairwells[0];
  for (double x = hole.min().x() + 0.05; x < hole.max().x() - 0.05; x += 0.1)
    for (double y = hole.min().y() + 0.05; y < hole.max().y() - 0.05; y += 0.1) {
      ASSERT_EQ(cell(b, x, y), kOcc) << x << ", " << y;
      ASSERT_TRUE(danger(b, x, y)) << x << ", " << y;
      ASSERT_TRUE(std::isnan(floorAt(b, x, y))) << x << ", " << y;
    }
  EXPECT_FALSE(danger(b, 10.0, 1.5));
  EXPECT_FALSE(danger(b, rx, 8.0));
  // Counts: the lab's open floor is most of it; the stairwell's cells are the danger ones.
  EXPECT_EQ(st.cells_occupied + st.cells_free + st.cells_unknown, b.grid.cells.size());
  EXPECT_GT(st.cells_free, 100000u);
  EXPECT_GT(st.cells_occupied, 20000u);
  EXPECT_GE(st.cells_danger, size_t(hole.volume() / 0.0025));
  EXPECT_LT(st.cells_danger, 10000u);
}

}  // namespace polyloc::t_map_height_band
