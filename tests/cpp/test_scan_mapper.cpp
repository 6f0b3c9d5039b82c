// Mapping with known poses: scans of a 6 x 4 m room, ranges from an analytic ray/wall
// intersection, at known laser poses. The grid has its occupied cells on the walls (within one
// cell, >= 95 % of the wall length covered), free cells inside, unknown outside; the grid grows
// without moving what it holds; bad scans are refused with the reason. Then gridFromRecording
// on a CARMEN log, and `polyloc map extrude --carmen` end to end: the extruded mesh, ray cast
// with Embree from the room centre, has its walls where the room's are.
#include <polyloc/io/recording.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/io/recording_grid.hpp>
#include <polyloc/map/scan_mapper.hpp>
#include <polyloc/raycast/embree.hpp>

#include "run_command.hpp"
#include "temp_dir.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

namespace polyloc::t_scan_mapper {  // the file's own: the suite is compiled in batches (unity build)
namespace {

// The room's walls: an axis-aligned rectangle, placed off the cell boundaries on purpose.
struct Room {
  double x0 = -2.98, y0 = -1.97, x1 = 3.02, y1 = 2.03;
  double cx() const { return (x0 + x1) / 2; }
  double cy() const { return (y0 + y1) / 2; }
  // Distance from (px, py) inside along (cos a, sin a) to the first wall.
  double ray(double px, double py, double a) const {
    const double dx = std::cos(a), dy = std::sin(a), inf = std::numeric_limits<double>::infinity();
    const double tx = dx > 1e-12 ? (x1 - px) / dx : dx < -1e-12 ? (x0 - px) / dx : inf;
    const double ty = dy > 1e-12 ? (y1 - py) / dy : dy < -1e-12 ? (y0 - py) / dy : inf;
    return std::min(tx, ty);
  }
  // Signed distance to the wall outline: < 0 inside.
  double signedDistance(double px, double py) const {
    const double ix = std::min(px - x0, x1 - px), iy = std::min(py - y0, y1 - py);
    if (ix >= 0 && iy >= 0) return -std::min(ix, iy);
    const double ox = std::max({x0 - px, px - x1, 0.0}), oy = std::max({y0 - py, py - y1, 0.0});
    return std::hypot(ox, oy);
  }
};

// An LMS-like scanner: 361 beams over 180 deg.
constexpr size_t kBeams = 361;
constexpr double kAngleMin = -M_PI / 2, kIncrement = M_PI / 360;

struct LaserPose { double x, y, yaw; };

// 12 places on a 4 x 3 lattice inside, each looking four ways: 48 scans.
std::vector<LaserPose> roomPoses(const Room& room) {
  std::vector<LaserPose> out;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k)
        out.push_back({room.x0 + 1.0 + 1.3 * i, room.y0 + 0.9 + 1.1 * j, k * M_PI / 2 + 0.1 * i});
  return out;
}

std::vector<float> scanOf(const Room& room, const LaserPose& p) {
  std::vector<float> r(kBeams);
  for (size_t k = 0; k < kBeams; ++k) r[k] = float(room.ray(p.x, p.y, p.yaw + kAngleMin + double(k) * kIncrement));
  return r;
}

ScanMapper mapRoom(const Room& room, const ScanMapperConfig& c = {}) {
  ScanMapper m(c);
  for (const auto& p : roomPoses(room)) {
    const auto r = scanOf(room, p);
    EXPECT_EQ(m.add(p.x, p.y, p.yaw, r.data(), r.size(), kAngleMin, kIncrement, 0.0, 80.0), ScanMapper::Added::Used);
  }
  return m;
}

// Checks the grid against the room: every occupied cell within one cell of a wall, >= 95 % of
// the wall length with an occupied cell within one cell, free inside, unknown outside.
void expectRoomGrid(const OccupancyGrid& g, const Room& room) {
  const double res = g.resolution;
  ASSERT_GT(g.width, 0u);
  size_t occupied = 0, inside = 0, inside_free = 0;
  for (size_t y = 0; y < g.height; ++y)
    for (size_t x = 0; x < g.width; ++x) {
      const double px = g.origin_x + (double(x) + 0.5) * res, py = g.origin_y + (double(y) + 0.5) * res;
      const double d = room.signedDistance(px, py);
      const int8_t v = g.at(x, y);
      if (v == OccupancyGrid::kOccupied) {
        ++occupied;
        // the cell the wall passes through, or its neighbour
        EXPECT_LE(std::fabs(d), 1.5 * res) << "occupied cell at " << px << ", " << py;
      }
      if (d < -1.5 * res) {
        ++inside;
        inside_free += v == OccupancyGrid::kFree;
      }
      if (d > 1.5 * res) {
        EXPECT_EQ(v, OccupancyGrid::kUnknown) << "outside cell at " << px << ", " << py;
      }
    }
  EXPECT_GT(occupied, 0u);
  EXPECT_GE(double(inside_free), 0.99 * double(inside)) << inside_free << " of " << inside << " inside cells free";
  // Along the outline in 1 cm steps: an occupied cell in the 3 x 3 cells around the point.
  const auto covered = [&](double px, double py) {
    const long ci = long(std::floor((px - g.origin_x) / res)), cj = long(std::floor((py - g.origin_y) / res));
    for (long j = cj - 1; j <= cj + 1; ++j)
      for (long i = ci - 1; i <= ci + 1; ++i)
        if (i >= 0 && j >= 0 && size_t(i) < g.width && size_t(j) < g.height && g.occupied(size_t(i), size_t(j))) return true;
    return false;
  };
  size_t samples = 0, hit = 0;
  for (double s = 0; s <= room.x1 - room.x0; s += 0.01) {
    samples += 2;
    hit += covered(room.x0 + s, room.y0) + covered(room.x0 + s, room.y1);
  }
  for (double s = 0; s <= room.y1 - room.y0; s += 0.01) {
    samples += 2;
    hit += covered(room.x0, room.y0 + s) + covered(room.x1, room.y0 + s);
  }
  EXPECT_GE(double(hit), 0.95 * double(samples)) << hit << " of " << samples << " wall samples covered";
}

TEST(ScanMapper, SquareRoomFromKnownPoses) {
  const Room room;
  ScanMapper m = mapRoom(room);
  EXPECT_EQ(m.scans(), 48u);
  const OccupancyGrid g = m.grid();
  EXPECT_DOUBLE_EQ(g.resolution, 0.05);
  EXPECT_EQ(g.origin_yaw, 0.0);
  // The observed area is the room (plus its wall cells) and 2 cells of padding.
  EXPECT_NEAR(g.origin_x, room.x0 - 3 * 0.05, 0.05 + 1e-9);
  EXPECT_NEAR(g.origin_y, room.y0 - 3 * 0.05, 0.05 + 1e-9);
  EXPECT_NEAR(double(g.width) * 0.05, room.x1 - room.x0 + 6 * 0.05, 0.1 + 1e-9);
  EXPECT_NEAR(double(g.height) * 0.05, room.y1 - room.y0 + 6 * 0.05, 0.1 + 1e-9);
  expectRoomGrid(g, room);
  // The padding ring is unknown.
  for (size_t x = 0; x < g.width; ++x) EXPECT_EQ(g.at(x, 0), OccupancyGrid::kUnknown);
}

TEST(ScanMapper, CoarserResolutionAndRoomAwayFromTheOrigin) {
  Room room;
  room.x0 += 40.013, room.x1 += 40.013, room.y0 -= 25.5, room.y1 -= 25.5;
  ScanMapperConfig c;
  c.resolution = 0.1;
  expectRoomGrid(mapRoom(room, c).grid(), room);
}

TEST(ScanMapper, GrowingKeepsWhatTheGridHolds) {
  const Room room;
  const OccupancyGrid before = mapRoom(room).grid();
  // The same room, then scans far away on every side: the grid grows four ways.
  ScanMapper m = mapRoom(room);
  const std::vector<float> far(kBeams, 2.0f);
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{-30, 0}, {30, 0}, {0, -25}, {0, 25}})
    ASSERT_EQ(m.add(x, y, 0, far.data(), far.size(), kAngleMin, kIncrement, 0, 80), ScanMapper::Added::Used);
  const OccupancyGrid after = m.grid();
  ASSERT_GT(after.width, before.width + 1000);
  ASSERT_GT(after.height, before.height + 900);
  const long dx = std::lround((before.origin_x - after.origin_x) / 0.05), dy = std::lround((before.origin_y - after.origin_y) / 0.05);
  ASSERT_GT(dx, 0);
  ASSERT_GT(dy, 0);
  size_t differ = 0;
  for (size_t y = 0; y < before.height; ++y)
    for (size_t x = 0; x < before.width; ++x) differ += before.at(x, y) != after.at(x + size_t(dx), y + size_t(dy));
  EXPECT_EQ(differ, 0u);
}

TEST(ScanMapper, MaxRangeBeamsOnlyClearFreeSpace) {
  ScanMapperConfig c;
  c.max_range = 3.0;
  ScanMapper m(c);
  // No return (+inf), a return at range_max, one beyond max_range: free up to 3 m, no wall.
  const float inf = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 5; ++k) {
    const float r[3] = {inf, 10.0f, 7.5f};
    ASSERT_EQ(m.add(0, 0, 0, r, 3, -0.1, 0.1, 0.0, 10.0), ScanMapper::Added::Used);
  }
  const OccupancyGrid g = m.grid();
  size_t occupied = 0, free = 0;
  double far_free = 0;
  for (size_t y = 0; y < g.height; ++y)
    for (size_t x = 0; x < g.width; ++x) {
      occupied += g.occupied(x, y);
      if (g.at(x, y) == OccupancyGrid::kFree) {
        ++free;
        far_free = std::max(far_free, std::hypot(g.origin_x + (x + 0.5) * 0.05, g.origin_y + (y + 0.5) * 0.05));
      }
    }
  EXPECT_EQ(occupied, 0u);
  EXPECT_GT(free, 120u);  // three beams of 60 cells, shared near the laser
  EXPECT_NEAR(far_free, 3.0, 0.08);
  // A hit inside max_range is a wall.
  ScanMapper hit(c);
  const float r[1] = {2.02f};
  ASSERT_EQ(hit.add(0, 0, 0, r, 1, 0, 0.1, 0, 10), ScanMapper::Added::Used);
  const OccupancyGrid h = hit.grid();
  const size_t ex = size_t(std::floor((2.02 - h.origin_x) / 0.05)), ey = size_t(std::floor((0.025 - h.origin_y) / 0.05));
  EXPECT_TRUE(h.occupied(ex, ey));
}

TEST(ScanMapper, BadScansAreRefusedWithTheReason) {
  ScanMapper m;
  const float ok[2] = {1, 2}, none[3] = {std::nanf(""), 0.0f, 0.05f};
  const double nan = std::nan("");
  EXPECT_EQ(m.add(nan, 0, 0, ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::BadPose);
  EXPECT_EQ(m.add(0, 0, std::numeric_limits<double>::infinity(), ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::BadPose);
  EXPECT_EQ(m.add(0, 0, 0, ok, 2, nan, 0.1, 0, 10), ScanMapper::Added::BadGeometry);
  EXPECT_EQ(m.add(0, 0, 0, ok, 2, 0, 0.1, 0, 0), ScanMapper::Added::BadGeometry);
  // NaN, CARMEN's 0 (no reading), below range_min
  EXPECT_EQ(m.add(0, 0, 0, none, 3, 0, 0.1, 0.1, 10), ScanMapper::Added::NoBeams);
  EXPECT_EQ(m.add(0, 0, 0, ok, 0, 0, 0.1, 0, 10), ScanMapper::Added::NoBeams);
  EXPECT_EQ(m.add(1e300, 0, 0, ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::TooLarge);  // no cell index
  EXPECT_EQ(m.scans(), 0u);
  EXPECT_EQ(m.grid().width, 0u);
  EXPECT_EQ(m.add(0, 0, 0, ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::Used);
  // A corrupt pose 1000 km away from what the grid holds: refused, the grid kept.
  const OccupancyGrid before = m.grid();
  EXPECT_EQ(m.add(1e6, 0, 0, ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::TooLarge);
  EXPECT_EQ(m.scans(), 1u);
  EXPECT_EQ(m.grid().cells, before.cells);
  // The grid may not grow beyond max_cells: a scan far away is refused, the grid kept.
  ScanMapperConfig small;
  small.max_cells = 100000;
  ScanMapper s(small);
  EXPECT_EQ(s.add(0, 0, 0, ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::Used);
  EXPECT_EQ(s.add(100, 100, 0, ok, 2, 0, 0.1, 0, 10), ScanMapper::Added::TooLarge);  // 2000 x 2000 cells
  EXPECT_EQ(s.scans(), 1u);
  EXPECT_LT(s.grid().width, 100u);
}

// Whether a scan fits max_cells depends on the cells observed, not on the margins the grid grew
// by: a robot driving 100 m along a line observes a 2,000 x 10 cell strip, which fits 100,000
// cells (the grid used to keep its 64-cell margins across the line and refuse every scan after
// 38 m, and, near the limit, copied the whole grid once per scan).
TEST(ScanMapper, ALongStripFitsTheBudgetItsCellsFit) {
  ScanMapperConfig small;
  small.max_cells = 100000;
  ScanMapper m(small);
  const float ranges[3] = {0.2f, 0.2f, 0.2f};
  for (int k = 0; k <= 200; ++k)
    ASSERT_EQ(m.add(0.5 * k, 0, 0, ranges, 3, -0.1, 0.1, 0, 10), ScanMapper::Added::Used) << "scan at x = " << 0.5 * k;
  const OccupancyGrid g = m.grid();
  EXPECT_NEAR(double(g.width) * g.resolution, 100.2, 0.3);
  EXPECT_LT(g.height, 20u);
  // The last scan's middle beam hit at x = 100.2 m (plus half a cell, hit_beyond).
  EXPECT_EQ(g.at(size_t((100.23 - g.origin_x) / g.resolution), size_t((0.01 - g.origin_y) / g.resolution)), OccupancyGrid::kOccupied);
}

TEST(ScanMapper, ConfigErrorsNameTheField) {
  const auto message = [](ScanMapperConfig c) {
    try {
      ScanMapper m(c);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ScanMapperConfig c;
  c.resolution = 0;
  EXPECT_NE(message(c).find("resolution"), std::string::npos);
  c = {}, c.miss = 0.1;
  EXPECT_NE(message(c).find("miss"), std::string::npos);
  c = {}, c.free_thresh = 0.7;
  EXPECT_NE(message(c).find("free_thresh"), std::string::npos);
  c = {}, c.clamp_min = -1.0;  // logit(0.196) = -1.41: never free
  EXPECT_NE(message(c).find("clamp_min"), std::string::npos);
  c = {}, c.max_range = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(c).find("max_range"), std::string::npos);
}

// A corrected CARMEN log of the room: FLASER lines with the laser pose, ODOM lines (noisy
// odometry, not used), PARAM lines for the LMS geometry. 40 scans along an ellipse through the
// room, looking ahead, then backwards.
std::string roomLog(const Room& room, int scans = 40) {
  std::string s = "# corrected log written by test_scan_mapper\n"
                  "PARAM laser_front_laser_fov 180 0 host 0\n"
                  "PARAM laser_front_laser_resolution 0.5 0 host 0\n"
                  "PARAM robot_front_laser_max 50.0 0 host 0\n";
  for (int i = 0; i < scans; ++i) {
    const double a = 2 * M_PI * i / scans * 2;  // twice round
    const LaserPose p{room.cx() + 2.0 * std::cos(a), room.cy() + 1.1 * std::sin(a), a + M_PI / 2 + (i >= scans / 2 ? M_PI : 0)};
    const std::string t = fmt::format("{}.{:03d} host {}\n", 100 + i / 10, (i % 10) * 100, i);
    s += fmt::format("ODOM {:.4f} {:.4f} {:.4f} 0.3 0.1 0 ", p.x + 0.2, p.y - 0.1, p.yaw + 0.05) + t;
    s += fmt::format("FLASER {}", kBeams);
    for (float r : scanOf(room, p)) s += fmt::format(" {:.4f}", r);
    s += fmt::format(" {:.6f} {:.6f} {:.6f} {:.4f} {:.4f} {:.4f} ", p.x, p.y, p.yaw, p.x + 0.2, p.y - 0.1, p.yaw + 0.05) + t;
  }
  return s;
}

TEST(RecordingGrid, CarmenLogScansAtTheirLaserPoses) {
  test::TempDir dir;
  const Room room;
  std::string log = roomLog(room);
  // A scan with no reading at all, and one whose pose line is broken (a bad line, counted by
  // the reader: no scan, no pose).
  log += "FLASER 3 0 0 0 0 0 0 0 0 0 200.0 host 0\n";
  log += "FLASER 3 1 1 1 0 x 0 0 0 0 200.1 host 0\n";
  auto reader = openRecording(dir.write("room.log", log));
  RecordingGridStats st;
  const OccupancyGrid g = gridFromRecording(*reader, {"/front_laser", "/rear_laser", "/robot_laser"}, {}, &st);
  EXPECT_EQ(st.scans_used, 40u);
  EXPECT_EQ(st.scansSkipped(), 1u);
  EXPECT_EQ(st.skipped["no_valid_ranges"], 1u);
  EXPECT_EQ(reader->stats().rejected, 1u);
  expectRoomGrid(g, room);
  // Only the rear laser: there is none.
  auto again = openRecording(dir.file("room.log"));
  RecordingGridStats none;
  EXPECT_EQ(gridFromRecording(*again, {"/rear_laser"}, {}, &none).width, 0u);
  EXPECT_EQ(none.scans_used, 0u);
}

TEST(RecordingGrid, ScansWithoutTheirPoseAreCounted) {
  // A recording of scans without pose messages (as a raw log from another tool would be).
  class Scans final : public RecordingReader {
   public:
    std::vector<TopicInfo> topics() override { return {}; }
    bool next(RecordedMessage& out) override {
      if (k_ == 3) return false;
      msg::LaserScan s;
      s.ranges = {1, 2};
      s.angle_increment = 0.1f;
      s.range_max = 10;
      out = {"/front_laser", k_, k_, s};
      ++k_;
      return true;
    }
    const ReadStats& stats() const override { return stats_; }
    std::string format() const override { return "test"; }

   private:
    int64_t k_ = 0;
    ReadStats stats_;
  } scans;
  RecordingGridStats st;
  EXPECT_EQ(gridFromRecording(scans, {"/front_laser"}, {}, &st).width, 0u);
  EXPECT_EQ(st.scans_used, 0u);
  EXPECT_EQ(st.skipped["no_pose"], 3u);
}

struct CliRun {
  int rc = -1;
  std::string out, err;
};

CliRun cli(const std::string& args, const test::TempDir& dir) {
  const test::CommandRun c = test::runCommand(std::string(POLYLOC_CLI) + " " + args + " 2>" + dir.file("stderr.txt"));
  std::ifstream in(dir.file("stderr.txt"));
  return {c.rc, c.out, std::string(std::istreambuf_iterator<char>(in), {})};
}

TEST(MapExtrudeCarmen, ExtrudedWallsAreWhereTheRoomsAre) {
  test::TempDir dir;
  const Room room;
  const std::string log = dir.write("room.log", roomLog(room));
  const CliRun r = cli("map extrude --carmen " + log + " --out " + dir.file("room.obj") + " --save-grid " +
                        dir.file("grid/room.yaml") + " --wall-height 2.5 --json",
                    dir);
  ASSERT_EQ(r.rc, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["scans_used"], 40);
  EXPECT_EQ(j["scans_skipped"], 0);
  EXPECT_EQ(j["closed"], true);
  EXPECT_DOUBLE_EQ(j["resolution_m"].get<double>(), 0.05);
  // The saved grid is the one that was extruded.
  const OccupancyGrid saved = loadGridMap(dir.file("grid/room.yaml"));
  EXPECT_EQ(saved.width, j["cells_x"].get<size_t>());
  expectRoomGrid(saved, room);

  // Rays from the room centre at mid height, every 5 deg: the true wall distance within 2 cells.
  const Mesh mesh = loadMesh(dir.file("room.obj"));
  EmbreeOptions one_thread;
  one_thread.threads = 1;
  EmbreeCaster caster(mesh, one_thread);
  constexpr size_t n = 72;
  std::vector<float> ox(n, float(room.cx())), oy(n, float(room.cy())), oz(n, 1.0f), dx(n), dy(n), dz(n, 0.0f), range(n);
  for (size_t k = 0; k < n; ++k) dx[k] = float(std::cos(k * 2 * M_PI / n)), dy[k] = float(std::sin(k * 2 * M_PI / n));
  caster.castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, n}, {range.data()});
  for (size_t k = 0; k < n; ++k)
    EXPECT_NEAR(range[k], room.ray(room.cx(), room.cy(), k * 2 * M_PI / n), 2 * 0.05) << "ray at " << k * 5 << " deg";
  // Straight down: the floor slab under the grid at z = 0.
  const float down_z = -1.0f;
  float down = 0;
  caster.castRays({ox.data(), oy.data(), oz.data(), dz.data(), dz.data(), &down_z, nullptr, nullptr, 1}, {&down});
  EXPECT_NEAR(down, 1.0f, 1e-4);
  // Up: open (no ceiling), and walls 2.5 m high: a ray at 2.6 m passes over them.
  std::vector<float> high(n, 2.6f), over(n);
  caster.castRays({ox.data(), oy.data(), high.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, n}, {over.data()});
  for (size_t k = 0; k < n; ++k) EXPECT_TRUE(std::isinf(over[k])) << k;
}

TEST(MapExtrudeCarmen, LaserChoiceAndBadInputNameTheFile) {
  test::TempDir dir;
  const Room room;
  const std::string log = dir.write("room.log", roomLog(room, 8));
  // Only the rear laser: this log has none.
  CliRun r = cli("map extrude --carmen " + log + " --laser rear --out " + dir.file("a.obj"), dir);
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find(log + ": no usable laser scan"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/rear_laser"), std::string::npos) << r.err;
  // A log without laser lines.
  const std::string odom = dir.write("odom.log", "PARAM robot_front_laser_max 50.0 0 host 0\nODOM 1 2 3 0 0 0 5.0 host 5.0\n");
  r = cli("map extrude --carmen " + odom + " --out " + dir.file("b.obj"), dir);
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("odom.log: no usable laser scan"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("b.obj")));
  // Neither or both of --grid and --carmen.
  r = cli("map extrude --out " + dir.file("c.obj"), dir);
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("exactly one of --grid and --carmen"), std::string::npos) << r.err;
  r = cli("map extrude --carmen " + log + " --grid " + log + " --out " + dir.file("c.obj"), dir);
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("excludes"), std::string::npos) << r.err;
  r = cli("map extrude --carmen " + log + " --laser left --out " + dir.file("c.obj"), dir);
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("--laser"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace polyloc
