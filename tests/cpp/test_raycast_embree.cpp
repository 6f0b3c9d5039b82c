// Embree backend against analytic geometry: a closed box room of solid wall slabs.
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/workload.hpp>

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_embree {

using namespace polyloc;
using polyloc::test::boxRoom;


constexpr float kInf = std::numeric_limits<float>::infinity();

// Interior [-2, 2] x [-1.5, 1.5] x [0, 3]; walls 0.2 m thick.
struct Room : ::testing::Test {
  Mesh mesh = boxRoom(2.f, 1.5f, 3.f, 0.2f);
  EmbreeCaster caster{mesh};

  float cast(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t0 = 0.f, float t1 = kInf,
             uint32_t* tri = nullptr, uint32_t* label = nullptr, Eigen::Vector3f* n = nullptr) {
    const Eigen::Vector3f u = d.normalized();
    RayBatch r{&o.x(), &o.y(), &o.z(), &u.x(), &u.y(), &u.z(), &t0, &t1, 1};
    float range;
    float nx, ny, nz;
    HitBuffers out{&range, tri, label, n ? &nx : nullptr, &ny, &nz};
    caster.castRays(r, out);
    if (n) *n = {nx, ny, nz};
    return range;
  }
};

// The scans' rays as explicit rays (castRays), ranges into `range` (poses x beams).
void castAsRays(const EmbreeCaster& caster, const std::vector<Pose>& poses, const BeamSet& beams, std::vector<float>& range) {
  const size_t n = poses.size() * beams.size();
  std::vector<float> ox(n), oy(n), oz(n), dx(n), dy(n), dz(n);
  for (size_t p = 0; p < poses.size(); ++p)
    for (size_t b = 0; b < beams.size(); ++b) {
      const size_t i = p * beams.size() + b;
      const Eigen::Vector3d d = poses[p].rotate({beams.dx[b], beams.dy[b], beams.dz[b]});
      ox[i] = poses[p].x(), oy[i] = poses[p].y(), oz[i] = poses[p].z();
      dx[i] = d.x(), dy[i] = d.y(), dz[i] = d.z();
    }
  range.resize(n);
  caster.castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, n}, {range.data()});
}


TEST_F(Room, RangesFromCentreMatchTheBox) {
  const BeamSet beams = horizontalFan(360);
  std::vector<float> range(beams.size());
  const Pose centre = Pose::fromXYZRPY(0, 0, 1.5, 0, 0, 0);
  caster.castScans({&centre, 1}, beams, {range.data()});
  for (size_t i = 0; i < beams.size(); ++i) {
    const double a = 2 * M_PI * i / 360;
    const double expected = std::min(2.0 / std::max(1e-12, std::abs(std::cos(a))),
                                     1.5 / std::max(1e-12, std::abs(std::sin(a))));
    EXPECT_NEAR(range[i], expected, 1e-4) << "beam " << i;
  }
}

TEST_F(Room, RotatedPoseRotatesTheScan) {
  // Facing +y, the forward beam meets the y = 1.5 wall.
  const BeamSet beams = horizontalFan(4);
  std::vector<float> range(4);
  const Pose p = Pose::fromXYZRPY(0.5, 0, 1, 0, 0, M_PI / 2);
  caster.castScans({&p, 1}, beams, {range.data()});
  EXPECT_NEAR(range[0], 1.5, 1e-5);  // forward = +y
  EXPECT_NEAR(range[1], 2.5, 1e-5);  // left = -x
  EXPECT_NEAR(range[2], 1.5, 1e-5);  // back = -y
  EXPECT_NEAR(range[3], 1.5, 1e-5);  // right = +x
}

TEST_F(Room, RaysIntoCornersHitTheCorner) {
  // Corners where a wall's end face meets the next wall: robust traversal must not leak.
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const Eigen::Vector3f d(2.f * sx, 1.5f * sy, 0.f);
      EXPECT_NEAR(cast({0, 0, 1}, d), 2.5, 1e-4) << sx << " " << sy;
      // The 3D corner where two walls meet the floor.
      const Eigen::Vector3f d3(2.f * sx, 1.5f * sy, -1.f);
      EXPECT_NEAR(cast({0, 0, 1}, d3), d3.norm(), 1e-4) << sx << " " << sy;
    }
}

TEST_F(Room, RaysParallelToWallsAndGrazing) {
  // Parallel to the y = +1.5 wall, 1 cm from it: hits the x = 2 wall.
  EXPECT_NEAR(cast({0, 1.49f, 1}, {1, 0, 0}), 2.0, 1e-5);
  // Parallel to the floor, 1 mm above it.
  EXPECT_NEAR(cast({0, 0, 0.001f}, {1, 0, 0}), 2.0, 1e-5);
  // Grazing the floor at 0.5 deg from 1 cm height: meets it 1.146 m ahead.
  const float e = 0.5f * M_PI / 180.f;
  uint32_t label = 0;
  const float r = cast({0, 0, 0.01f}, {std::cos(e), 0, -std::sin(e)}, 0, kInf, nullptr, &label);
  EXPECT_NEAR(r, 0.01 / std::sin(e), 1e-3);
  EXPECT_EQ(mesh.label_names[label], "floor");
}

TEST_F(Room, LabelTriangleAndNormalOfTheHit) {
  uint32_t tri = 0, label = 0;
  Eigen::Vector3f n;
  EXPECT_NEAR(cast({0, 0, 1}, {1, 0, 0}, 0, kInf, &tri, &label, &n), 2.0, 1e-5);
  EXPECT_EQ(mesh.label_names[label], "wall");
  EXPECT_EQ(mesh.labelOf(tri), "wall");
  EXPECT_TRUE(n.isApprox(Eigen::Vector3f(-1, 0, 0), 1e-6)) << n.transpose();
  EXPECT_NEAR(cast({0, 0, 1}, {0, 0, -1}, 0, kInf, &tri, &label, &n), 1.0, 1e-5);
  EXPECT_EQ(mesh.label_names[label], "floor");
  EXPECT_TRUE(n.isApprox(Eigen::Vector3f(0, 0, 1), 1e-6));
  EXPECT_NEAR(cast({0, 0, 1}, {0, 0, 1}, 0, kInf, &tri, &label, &n), 2.0, 1e-5);
  EXPECT_EQ(mesh.label_names[label], "ceiling");
  // A miss reports kNoHit, label 0 and a zero normal.
  EXPECT_EQ(cast({0, 0, 10}, {0, 0, 1}, 0, kInf, &tri, &label, &n), kInf);
  EXPECT_EQ(tri, kNoHit);
  EXPECT_EQ(label, 0u);
  EXPECT_EQ(n, Eigen::Vector3f::Zero());
}

TEST_F(Room, OriginInsideSolid) {
  // Inside the x = +2 wall slab (2 .. 2.2): the first surface is the slab's back face.
  uint32_t tri = 0;
  EXPECT_EQ(cast({2.1f, 0, 1}, {1, 0, 0}, 0, kInf, &tri), 0.f);
  EXPECT_NE(tri, kNoHit);
  EXPECT_EQ(cast({2.1f, 0, 1}, {-1, 0, 0}), 0.f);
  caster.options.backface_is_solid = false;  // plain geometry: the slab's far face
  EXPECT_NEAR(cast({2.1f, 0, 1}, {1, 0, 0}), 0.1, 1e-5);
  EXPECT_NEAR(cast({2.1f, 0, 1}, {-1, 0, 0}), 0.1, 1e-5);
}

TEST_F(Room, WindowsLimitTheRay) {
  const Eigen::Vector3f o(0, 0, 1), d(1, 0, 0);  // wall at 2.0
  EXPECT_EQ(cast(o, d, 0.f, 1.5f), kInf);          // window ends before the wall
  EXPECT_NEAR(cast(o, d, 1.9f, 2.1f), 2.0, 1e-5);  // window around the wall
  EXPECT_NEAR(cast(o, d, 2.05f, 3.f), 2.05, 1e-5);  // window starts inside the wall
  EXPECT_EQ(cast(o, d, 2.5f, 2.4f), kInf);          // empty window
  EXPECT_EQ(cast(o, d, 2.3f, 5.f), kInf);           // beyond the wall: nothing (room closed)
  caster.options.miss_is_max_range = true;
  EXPECT_FLOAT_EQ(cast(o, d, 0.f, 1.5f), 1.5f);
}

TEST_F(Room, ScanWindowsAndSensorLimits) {
  BeamSet beams = horizontalFan(4);  // +x: 2.0, +y: 1.5, -x: 2.0, -y: 1.5
  beams.range_max = 1.8f;
  std::vector<float> range(4);
  const Pose p = Pose::fromXYZRPY(0, 0, 1, 0, 0, 0);
  caster.castScans({&p, 1}, beams, {range.data()});
  EXPECT_EQ(range[0], kInf);
  EXPECT_NEAR(range[1], 1.5, 1e-5);
  beams.range_max = 30.f;
  const float tmin[4] = {1.9f, 0.f, 0.f, 1.6f}, tmax[4] = {2.1f, 1.4f, 30.f, 30.f};
  caster.castScans({&p, 1}, beams, {range.data()}, {tmin, tmax});
  EXPECT_NEAR(range[0], 2.0, 1e-5);
  EXPECT_EQ(range[1], kInf);
  EXPECT_NEAR(range[2], 2.0, 1e-5);
  EXPECT_NEAR(range[3], 1.6, 1e-5);  // starts inside the -y wall slab
}

TEST_F(Room, TiltedScannerSeesTheFloor) {
  // Scanner 0.5 m up, pitched 40 deg down: the forward beam meets the floor at 0.5 / sin 40.
  const BeamSet beams = horizontalFan(1);
  float range;
  const Pose p = Pose::fromXYZRPY(0, 0, 0.5, 0, 40 * M_PI / 180, 0);
  caster.castScans({&p, 1}, beams, {&range});
  EXPECT_NEAR(range, 0.5 / std::sin(40 * M_PI / 180), 1e-5);
}

TEST_F(Room, SameResultsForOneAndTwoThreadsAndAllPaths) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(-1.9f, 1.9f), uy(-1.4f, 1.4f), ua(-3.1f, 3.1f);
  std::vector<Pose> poses;
  for (int i = 0; i < 2000; ++i)
    poses.push_back(Pose::fromXYZRPY(ux(rng), uy(rng), 0.3, 0.05, -0.03, ua(rng)));
  const BeamSet beams = horizontalFan(100);
  const size_t n = poses.size() * beams.size();
  std::vector<float> r1(n), r2(n), single(n);
  std::vector<uint32_t> t1(n), t2(n);
  caster.setThreads(1);
  EXPECT_EQ(caster.threads(), 1);
  caster.castScans(poses, beams, {r1.data(), t1.data()});
  caster.setThreads(2);
  caster.castScans(poses, beams, {r2.data(), t2.data()});
  caster.castScansSingle(poses, beams, single.data());
  EXPECT_EQ(r1, r2);
  EXPECT_EQ(t1, t2);
  for (size_t i = 0; i < n; ++i) ASSERT_NEAR(r1[i], single[i], 1e-5) << i;
  // Explicit rays (b) give the same ranges as scans (a).
  std::vector<float> rb(n);
  castAsRays(caster, poses, beams, rb);
  for (size_t i = 0; i < n; ++i) ASSERT_NEAR(r1[i], rb[i], 1e-4) << i;
}

TEST_F(Room, FreeSpaceAndClearance) {
  const std::vector<Eigen::Vector3f> pts = {
      {0, 0, 1},       // centre of the room
      {1.9f, 0, 1},    // 0.1 m from the x = 2 wall
      {2.1f, 0, 1},    // inside the wall slab
      {0, 0, -0.1f},   // inside the floor slab
      {0, 0, 5},       // above the ceiling slab, outside every solid
  };
  std::vector<uint8_t> free(pts.size());
  caster.queryFree(pts, 0.f, free.data());
  EXPECT_EQ(free, (std::vector<uint8_t>{1, 1, 0, 0, 1}));
  caster.queryFree(pts, 0.3f, free.data());
  EXPECT_EQ(free, (std::vector<uint8_t>{1, 0, 0, 0, 1}));
  caster.queryFree(pts, 0.95f, free.data());  // centre is 1.0 m above the floor, its nearest surface
  EXPECT_EQ(free[0], 1);
  caster.queryFree(pts, 1.05f, free.data());
  EXPECT_EQ(free[0], 0);
}

TEST(EmbreeCaster, RejectsEmptyMap) {
  Mesh empty;
  EXPECT_THROW(EmbreeCaster{empty}, std::invalid_argument);
}

// A triangle naming a vertex the mesh lacks is found after Embree's device and scene exist: the
// throw releases them (RAII owners; `make sanitize` runs this under LeakSanitizer, which failed
// on the caster that leaked both), and a caster built after it works.
TEST(EmbreeCaster, AThrowHalfWayReleasesTheDeviceAndTheScene) {
  Mesh bad;
  bad.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bad.triangles = {{0, 1, 2}, {0, 1, 7}};
  for (int k = 0; k < 20; ++k) {
    try {
      EmbreeCaster c(bad);
      ADD_FAILURE() << "a missing vertex was taken";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("triangle 1 references a missing vertex"), std::string::npos) << e.what();
    }
  }
  bad.triangles.pop_back();
  const EmbreeCaster good(bad);
  const Eigen::Vector3f o(0.2f, 0.2f, 1.f), d(0, 0, -1);
  const RayBatch ray{&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), nullptr, nullptr, 1};
  float r = 0;
  good.castRays(ray, {&r});
  EXPECT_NEAR(r, 1.f, 1e-5f);
}

// Embree asserts (SIGABRT) on a ray with a coordinate beyond ~1.8e18 or a NaN window; the caster
// reports such a ray as a miss, and the good rays of the same packet are unaffected.
TEST_F(Room, RaysOutsideEmbreesDomainAreMisses) {
  const float big = 1e19f, nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(cast({big, 0, 1}, {1, 0, 0}), kInf);
  EXPECT_EQ(cast({0, 0, 1}, {1, 0, 0}, nan, kInf), kInf);
  EXPECT_EQ(cast({0, 0, 1}, {1, 0, 0}, 0.f, nan), kInf);
  EXPECT_NEAR(cast({0, 0, 1}, {1, 0, 0}), 2.f, 1e-5);
  const std::vector<float> ox = {0, big, 0}, oy = {0, 0, 0}, oz = {1, 1, 1};
  const std::vector<float> dx = {1, 1, 1e30f}, dy = {0, 0, 0}, dz = {0, 0, 0};
  std::vector<float> r(3);
  caster.castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, 3}, {r.data()});
  EXPECT_NEAR(r[0], 2.f, 1e-5);
  EXPECT_EQ(r[1], kInf);
  EXPECT_EQ(r[2], kInf);
  const BeamSet beams = horizontalFan(16);
  std::vector<float> range(beams.size() * 2);
  const Pose poses[2] = {Pose::fromXYZRPY(1e19, 0, 1, 0, 0, 0), Pose::fromXYZRPY(0, 0, 1, 0, 0, 0)};
  caster.castScans(poses, beams, {range.data()});
  for (size_t b = 0; b < beams.size(); ++b) EXPECT_EQ(range[b], kInf) << b;
  EXPECT_NEAR(range[beams.size()], 2.f, 1e-5);  // the sane pose's forward beam
  const std::vector<Eigen::Vector3f> pts = {{big, 0, 1}, {0, 0, 1}};
  std::vector<uint8_t> free(2);
  caster.queryFree(pts, 0.1f, free.data());
  EXPECT_EQ(free, (std::vector<uint8_t>{0, 1}));
}

// Touching closed solids share faces: a row of unit cubes, each face against its neighbour's. A
// ray from inside a cube meets its exit face and the next cube's entry face at the same
// distance; Embree alone keeps whichever its traversal met last, so packets and single rays
// disagreed (an office map of touching boxes: 372 of 2,000,000 rays). Both paths must give the
// back face: the origin is inside a solid, the range is the window start.
TEST(EmbreeCaster, TouchingSolidsGiveOneAnswerOnEveryPath) {
  Mesh mesh;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) mesh.addBox({double(i), double(j), 0}, {i + 1.0, j + 1.0, 1.0}, uint32_t(1 + i * 8 + j));
  EmbreeCaster caster(mesh);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.05f, 7.95f), a(-3.14f, 3.14f);
  std::vector<Pose> poses;
  for (int i = 0; i < 400; ++i) poses.push_back(Pose::fromXYZRPY(u(rng), u(rng), 0.5, 0, 0, a(rng)));
  // Beams along the grid axes and diagonals too: they run through the shared faces and edges.
  const BeamSet beams = horizontalFan(360, 20.f);
  const size_t n = poses.size() * beams.size();
  std::vector<float> packets(n), single(n), rays(n);
  std::vector<uint32_t> tri(n);
  caster.castScans(poses, beams, {packets.data(), tri.data()});
  caster.castScansSingle(poses, beams, single.data());
  castAsRays(caster, poses, beams, rays);
  size_t inside = 0;
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(packets[i], single[i]) << "ray " << i;
    ASSERT_EQ(packets[i], rays[i]) << "ray " << i;
    ASSERT_NE(tri[i], kNoHit) << "ray " << i;  // every origin is inside a cube
    inside += packets[i] == beams.range_min;
  }
  EXPECT_EQ(inside, n);  // from inside a solid: the window start, never the neighbour's face
}

}  // namespace polyloc::t_raycast_embree
