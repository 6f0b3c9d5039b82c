// ROS map_server grids: PGM + YAML round trip, map_server's thresholds and negate, and errors
// that name the file and the key.
#include <polyloc/map/grid_map.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <functional>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_map_grid {

using namespace polyloc;
using polyloc::test::TempDir;


// A 4 x 3 grid: occupied, free and unknown cells at known places.
OccupancyGrid sample() {
  OccupancyGrid g;
  g.resize(4, 3, OccupancyGrid::kFree);
  g.resolution = 0.1;
  g.origin_x = -1.5, g.origin_y = 2.25, g.origin_yaw = 0.0;
  g.at(0, 0) = OccupancyGrid::kOccupied;
  g.at(3, 2) = OccupancyGrid::kOccupied;
  g.at(1, 2) = OccupancyGrid::kUnknown;
  return g;
}

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const GridMapError& e) {
    return e.what();
  }
  return "no error";
}


TEST(GridMap, RoundTripKeepsCellsAndGeometry) {
  TempDir dir;
  const OccupancyGrid g = sample();
  saveGridMap(g, dir.file("m.yaml"));
  const OccupancyGrid back = loadGridMap(dir.file("m.yaml"));
  EXPECT_EQ(back.width, 4u);
  EXPECT_EQ(back.height, 3u);
  EXPECT_DOUBLE_EQ(back.resolution, 0.1);
  EXPECT_DOUBLE_EQ(back.origin_x, -1.5);
  EXPECT_DOUBLE_EQ(back.origin_y, 2.25);
  EXPECT_EQ(back.cells, g.cells);
}

TEST(GridMap, ReadsMapServerThresholdsAndNegate) {
  TempDir dir;
  // 3 x 1 image, top row first: black, mid grey, white.
  dir.write("g.pgm", std::string("P5\n3 1\n255\n") + char(0) + char(128) + char(255));
  dir.write("g.yaml", "image: g.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                      "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const OccupancyGrid g = loadGridMap(dir.file("g.yaml"));
  EXPECT_EQ(g.at(0, 0), OccupancyGrid::kOccupied);
  EXPECT_EQ(g.at(1, 0), OccupancyGrid::kUnknown);
  EXPECT_EQ(g.at(2, 0), OccupancyGrid::kFree);
  dir.write("n.yaml", "image: g.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 1\n"
                      "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const OccupancyGrid n = loadGridMap(dir.file("n.yaml"));
  EXPECT_EQ(n.at(0, 0), OccupancyGrid::kFree);
  EXPECT_EQ(n.at(2, 0), OccupancyGrid::kOccupied);
}

TEST(GridMap, BadInputNamesFileAndKey) {
  TempDir dir;
  saveGridMap(sample(), dir.file("ok.yaml"));
  const std::string head = "image: ok.pgm\norigin: [0, 0, 0]\nnegate: 0\nfree_thresh: 0.2\n";
  struct Case {
    std::string yaml, expect;
  } cases[] = {
      {head + "occupied_thresh: 0.65\n", "resolution"},                        // missing key
      {head + "occupied_thresh: 0.65\nresolution: -1\n", "resolution"},        // bad value
      {head + "occupied_thresh: 1.5\nresolution: 0.05\n", "occupied_thresh"},  // out of range
      {head + "occupied_thresh: 0.1\nresolution: 0.05\n", "free_thresh"},      // free >= occupied
      {head + "occupied_thresh: 0.65\nresolution: 0.05\nmode: scale\n", "mode"},
      {head + "occupied_thresh: 0.65\nresolution: 0.05\ncolour: 3\n", "colour"},  // unknown key
      {"image: ok.pgm\norigin: [0, 0]\nnegate: 0\nfree_thresh: 0.2\noccupied_thresh: 0.65\nresolution: 0.05\n", "origin"},
      {"image: gone.pgm\norigin: [0, 0, 0]\nnegate: 0\nfree_thresh: 0.2\noccupied_thresh: 0.65\nresolution: 0.05\n", "gone.pgm"},
  };
  for (const Case& c : cases) {
    const std::string path = dir.write("bad.yaml", c.yaml);
    const std::string m = message([&] { loadGridMap(path); });
    EXPECT_NE(m.find("bad.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find(c.expect), std::string::npos) << m;
  }
  EXPECT_NE(message([&] { loadGridMap(dir.file("none.yaml")); }).find("none.yaml"), std::string::npos);
  dir.write("broken.pgm", "P5\n3 1\n");  // truncated header
  const std::string p = dir.write("b.yaml", "image: broken.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                                            "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  EXPECT_NE(message([&] { loadGridMap(p); }).find("broken.pgm"), std::string::npos);
}

}  // namespace polyloc::t_map_grid
