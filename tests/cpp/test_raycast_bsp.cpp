// BSP backend: hand-computed ranges in the box room (touching slabs, so the union step is
// exercised), windows and inside-solid rules, free space with clearance, agreement with Embree
// on the bundled lab map, and the error on open or inward geometry.
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/bsp.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/workload.hpp>

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_bsp {

using namespace polyloc;


constexpr float kInf = std::numeric_limits<float>::infinity();

struct Hit {
  float range;
  uint32_t tri, label;
  Eigen::Vector3f n;
};

Hit castOne(const RayCaster& c, Eigen::Vector3f o, Eigen::Vector3f d, float t0 = 0.f,
            float t1 = kInf) {
  d.normalize();
  Hit h{};
  RayBatch r{&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), &t0, &t1, 1};
  c.castRays(r, {&h.range, &h.tri, &h.label, &h.n.x(), &h.n.y(), &h.n.z()});
  return h;
}

// Interior [-2, 2] x [-1.5, 1.5] x [0, 3], slabs 0.2 m thick.
struct BspRoom : ::testing::Test {
  Mesh mesh = test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  BspCaster bsp{mesh};
};


TEST_F(BspRoom, BuildIsCompactAndTouchingFacesAreGone) {
  const BspStats& s = bsp.stats();
  EXPECT_EQ(s.input_triangles, mesh.numTriangles());
  EXPECT_LT(s.boundary_polygons, s.input_triangles);  // faces between touching slabs dropped
  EXPECT_GT(s.nodes, 0u);
  EXPECT_EQ(s.node_bytes, s.nodes * 32);
  EXPECT_GT(s.solid_leaves, 0u);
  EXPECT_GT(s.empty_leaves, 0u);
}

TEST_F(BspRoom, KnownRanges) {
  // From (0.5, -0.5, 1): walls at x = 2 (1.5 m), x = -2 (2.5), y = 1.5 (2.0), y = -1.5 (1.0),
  // floor 1.0 below, ceiling 2.0 above; the diagonal (1, 1, 0) meets y = 1.5 first, at 2 sqrt 2.
  const Eigen::Vector3f o(0.5f, -0.5f, 1.f);
  EXPECT_NEAR(castOne(bsp, o, {1, 0, 0}).range, 1.5, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, {-1, 0, 0}).range, 2.5, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, {0, 1, 0}).range, 2.0, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, {0, -1, 0}).range, 1.0, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, {0, 0, -1}).range, 1.0, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, {0, 0, 1}).range, 2.0, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, {1, 1, 0}).range, 1.5 * std::sqrt(2.0), 1e-5);
  // Into the corner (2, 1.5, 0) from the centre at height 1: its full length.
  EXPECT_NEAR(castOne(bsp, {0, 0, 1}, {2, 1.5f, -1}).range, std::sqrt(4 + 2.25 + 1), 1e-4);
  // A scan from the centre: min(2 / |cos a|, 1.5 / |sin a|).
  const BeamSet beams = horizontalFan(72);
  std::vector<float> range(beams.size());
  const Pose centre = Pose::fromXYZRPY(0, 0, 1.5, 0, 0, 0);
  bsp.castScans({&centre, 1}, beams, {range.data()});
  for (size_t i = 0; i < beams.size(); ++i) {
    const double a = 2 * M_PI * i / beams.size();
    const double expected = std::min(2.0 / std::max(1e-12, std::abs(std::cos(a))),
                                     1.5 / std::max(1e-12, std::abs(std::sin(a))));
    EXPECT_NEAR(range[i], expected, 1e-4) << "beam " << i;
  }
}

TEST_F(BspRoom, NormalTriangleAndLabel) {
  Hit h = castOne(bsp, {0, 0, 1}, {1, 0, 0});
  EXPECT_TRUE(h.n.isApprox(Eigen::Vector3f(-1, 0, 0), 1e-6)) << h.n.transpose();
  ASSERT_NE(h.tri, kNoHit);
  EXPECT_EQ(mesh.labelOf(h.tri), "wall");
  EXPECT_EQ(mesh.label_names[h.label], "wall");
  EXPECT_TRUE(mesh.triangleNormal(h.tri).isApprox(h.n, 1e-5));
  h = castOne(bsp, {0, 0, 1}, {0, 0, -1});
  EXPECT_EQ(mesh.label_names[h.label], "floor");
  EXPECT_TRUE(h.n.isApprox(Eigen::Vector3f(0, 0, 1), 1e-6));
  h = castOne(bsp, {0, 0, 5}, {0, 0, 1});  // above the ceiling, going up: nothing
  EXPECT_EQ(h.range, kInf);
  EXPECT_EQ(h.tri, kNoHit);
  EXPECT_EQ(h.label, 0u);
  EXPECT_EQ(h.n, Eigen::Vector3f::Zero());
}

TEST_F(BspRoom, WindowsAndInsideSolid) {
  const Eigen::Vector3f o(0, 0, 1), d(1, 0, 0);  // wall slab 2.0 .. 2.2
  EXPECT_EQ(castOne(bsp, o, d, 0.f, 1.5f).range, kInf);
  EXPECT_NEAR(castOne(bsp, o, d, 1.9f, 2.1f).range, 2.0, 1e-5);
  EXPECT_NEAR(castOne(bsp, o, d, 2.05f, 3.f).range, 2.05, 1e-5);  // starts in the slab
  EXPECT_EQ(castOne(bsp, o, d, 2.5f, 2.4f).range, kInf);          // empty window
  EXPECT_EQ(castOne(bsp, o, d, 2.3f, 5.f).range, kInf);           // beyond the slab
  // Origin inside the slab: window start, or the far face when back faces are plain surfaces.
  Hit h = castOne(bsp, {2.1f, 0, 1}, {1, 0, 0});
  EXPECT_EQ(h.range, 0.f);
  EXPECT_TRUE(h.n.isApprox(Eigen::Vector3f(1, 0, 0), 1e-6));  // the back face it leaves by
  // Origin on the floor surface: the side the ray goes into decides (up: the ceiling, down: solid).
  EXPECT_NEAR(castOne(bsp, {0.3f, 0.2f, 0.f}, {0.1f, 0, 1}).range, std::sqrt(9.09), 1e-4);
  EXPECT_EQ(castOne(bsp, {0.3f, 0.2f, 0.f}, {0.1f, 0, -1}).range, 0.f);
  bsp.options.backface_is_solid = false;
  EXPECT_NEAR(castOne(bsp, {2.1f, 0, 1}, {1, 0, 0}).range, 0.1, 1e-5);
  EXPECT_NEAR(castOne(bsp, {2.1f, 0, 1}, {-1, 0, 0}).range, 0.1, 1e-5);
  bsp.options.backface_is_solid = true;
  bsp.options.miss_is_max_range = true;
  EXPECT_FLOAT_EQ(castOne(bsp, o, d, 0.f, 1.5f).range, 1.5f);
  // Scan windows narrow the sensor's limits per beam.
  bsp.options.miss_is_max_range = false;
  const BeamSet beams = horizontalFan(4);  // +x 2.0, +y 1.5, -x 2.0, -y 1.5
  std::vector<float> range(4);
  const Pose p = Pose::fromXYZRPY(0, 0, 1, 0, 0, 0);
  const float tmin[4] = {1.9f, 0.f, 0.f, 1.6f}, tmax[4] = {2.1f, 1.4f, 30.f, 30.f};
  bsp.castScans({&p, 1}, beams, {range.data()}, {tmin, tmax});
  EXPECT_NEAR(range[0], 2.0, 1e-5);
  EXPECT_EQ(range[1], kInf);
  EXPECT_NEAR(range[2], 2.0, 1e-5);
  EXPECT_NEAR(range[3], 1.6, 1e-5);
}

TEST_F(BspRoom, FreeSpaceWithAndWithoutClearance) {
  const std::vector<Eigen::Vector3f> pts = {
      {0, 0, 1},      // room centre: 1.0 m from the floor, its nearest surface
      {1.9f, 0, 1},   // 0.1 m from the x = 2 wall
      {2.1f, 0, 1},   // inside the wall slab
      {0, 0, -0.1f},  // inside the floor slab
      {0, 0, 5},      // above the ceiling, outside every solid
      {2.1f, 1.6f, 1},  // inside a corner post
  };
  std::vector<uint8_t> free(pts.size());
  bsp.queryFree(pts, 0.f, free.data());
  EXPECT_EQ(free, (std::vector<uint8_t>{1, 1, 0, 0, 1, 0}));
  bsp.queryFree(pts, 0.05f, free.data());
  EXPECT_EQ(free, (std::vector<uint8_t>{1, 1, 0, 0, 1, 0}));
  bsp.queryFree(pts, 0.3f, free.data());
  EXPECT_EQ(free, (std::vector<uint8_t>{1, 0, 0, 0, 1, 0}));
  bsp.queryFree(pts, 0.95f, free.data());
  EXPECT_EQ(free[0], 1);
  bsp.queryFree(pts, 1.05f, free.data());
  EXPECT_EQ(free[0], 0);
}

TEST_F(BspRoom, SameResultsForAnyThreadCount) {
  const std::vector<Pose> poses = randomPlanarPoses(mesh.bounds(), 500, 0.3, 3);
  const BeamSet beams = horizontalFan(64);
  const size_t n = poses.size() * beams.size();
  std::vector<float> r1(n), r2(n);
  bsp.setThreads(1);
  bsp.castScans(poses, beams, {r1.data()});
  bsp.setThreads(2);
  EXPECT_EQ(bsp.threads(), 2);
  bsp.castScans(poses, beams, {r2.data()});
  EXPECT_EQ(r1, r2);
}

TEST(BspCaster, RejectsOpenAndInwardGeometry) {
  Mesh open = test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  open.source = "maps/open_box.obj";
  open.triangles.pop_back();  // a hole in one slab
  open.triangle_label.pop_back();
  try {
    BspCaster c{open};
    FAIL() << "an open box was accepted";
  } catch (const MapError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("maps/open_box.obj: 3 open edges, e.g. at ("), std::string::npos) << msg;
    EXPECT_NE(msg.find("bsp needs closed, outward-facing solids"), std::string::npos) << msg;
  }
  Mesh inward = test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  for (Triangle& t : inward.triangles) std::swap(t[1], t[2]);
  try {
    BspCaster c{inward};
    FAIL() << "an inside-out map was accepted";
  } catch (const MapError& e) {
    EXPECT_NE(std::string(e.what()).find("face inward"), std::string::npos) << e.what();
  }
  EXPECT_THROW(BspCaster{Mesh{}}, std::invalid_argument);
}

// Reference point-in-solid, independent of both casters: the winding number of the whole mesh
// (solid angles of all triangles over 4 pi, Van Oosterom & Strackee). For a union of closed,
// outward solids it counts the solids around the point, so > 0.5 is inside.
static bool insideByWinding(const Mesh& m, const Eigen::Vector3f& p) {
  double omega = 0;
  for (const Triangle& t : m.triangles) {
    const Eigen::Vector3d a = (m.vertices[t[0]] - p).cast<double>();
    const Eigen::Vector3d b = (m.vertices[t[1]] - p).cast<double>();
    const Eigen::Vector3d c = (m.vertices[t[2]] - p).cast<double>();
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    omega += 2 * std::atan2(a.dot(b.cross(c)),
                            la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return omega / (4 * M_PI) > 0.5;
}

// The bundled lab map is closed and outward (polyloc map info); over thousands of random rays
// from free space the BSP and Embree ranges agree within 1 mm for at least 99.9 %, and the BSP's
// point-in-solid agrees with the winding number for 99.9 % of random points.
TEST(BspCaster, AgreesWithEmbreeOnTheLabMap) {
  const Mesh mesh = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  const BspCaster bsp{mesh};
  const EmbreeCaster embree{mesh};
  std::mt19937 rng(11);
  const Eigen::AlignedBox3f box = mesh.bounds();
  std::uniform_real_distribution<float> u01(0.f, 1.f);
  std::normal_distribution<float> g;
  std::vector<Eigen::Vector3f> pts;
  while (pts.size() < 8000)
    pts.push_back(box.min() + box.sizes().cwiseProduct(Eigen::Vector3f(u01(rng), u01(rng), u01(rng))));
  std::vector<uint8_t> free(pts.size());
  bsp.queryFree(pts, 0.f, free.data());
  size_t agree = 0;
  const size_t scored = pts.size();
  std::vector<float> ox, oy, oz, dx, dy, dz;
  for (size_t i = 0; i < pts.size(); ++i) {
    const bool inside = insideByWinding(mesh, pts[i]);
    agree += free[i] == (inside ? 0 : 1);
    if (inside) continue;
    for (int planar : {0, 1}) {  // a 3D and a planar ray from each free point
      Eigen::Vector3f d(g(rng), g(rng), planar ? 0.f : g(rng));
      d.normalize();
      ox.push_back(pts[i].x()), oy.push_back(pts[i].y()), oz.push_back(pts[i].z());
      dx.push_back(d.x()), dy.push_back(d.y()), dz.push_back(d.z());
    }
  }
  EXPECT_GE(double(agree), 0.999 * double(scored)) << agree << " of " << scored;
  const size_t n = ox.size();
  ASSERT_GT(n, 5000u);
  std::vector<float> rb(n), re(n);
  const RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr,
                      nullptr, n};
  bsp.castRays(rays, {rb.data()});
  embree.castRays(rays, {re.data()});
  size_t same = 0;
  for (size_t i = 0; i < n; ++i)
    same += (std::isinf(rb[i]) && std::isinf(re[i])) || std::abs(rb[i] - re[i]) <= 1e-3f;
  EXPECT_GE(double(same), 0.999 * double(n)) << same << " of " << n;
  std::printf("lab: %zu of %zu points, %zu of %zu ranges agree\n", agree, scored, same, n);
}

// Scans with per-beam windows: where a window starts in free space (1 cm clear), the same ranges
// as Embree on the lab; where it starts inside solid, the window start. (Embree answers
// otherwise there when the solid overlaps another one: from inside the loading platform its ray
// meets a wall face inside the platform first; the winding number sides with the BSP.)
TEST(BspCaster, ScansWithWindowsOnTheLabMap) {
  const Mesh mesh = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  BspCaster bsp{mesh};
  EmbreeCaster embree{mesh};
  std::vector<Pose> poses = randomPlanarPoses(mesh.bounds(), 400, 0.25, 5);
  BeamSet beams = horizontalFan(90, 8.f, 0.1f);
  std::vector<float> tmin(beams.size()), tmax(beams.size());
  for (size_t b = 0; b < beams.size(); ++b) {  // windows of 1 m at staggered distances
    tmin[b] = 0.5f * float(b % 8);
    tmax[b] = tmin[b] + 1.f;
  }
  const size_t n = poses.size() * beams.size();
  std::vector<Eigen::Vector3f> starts(n);
  for (size_t p = 0; p < poses.size(); ++p)
    for (size_t b = 0; b < beams.size(); ++b) {
      const float t0 = std::max(tmin[b], beams.range_min);
      starts[p * beams.size() + b] =
          (poses[p].translation() + t0 * poses[p].rotate({beams.dx[b], beams.dy[b], 0})).cast<float>();
    }
  std::vector<uint8_t> clear(n), solid(n);
  bsp.queryFree(starts, 0.01f, clear.data());
  bsp.queryFree(starts, 0.f, solid.data());  // 1 = free here; flipped below
  std::vector<float> rb(n), re(n);
  for (bool max_range : {false, true}) {
    bsp.options.miss_is_max_range = embree.options.miss_is_max_range = max_range;
    bsp.castScans(poses, beams, {rb.data()}, {tmin.data(), tmax.data()});
    embree.castScans(poses, beams, {re.data()}, {tmin.data(), tmax.data()});
    size_t same = 0, scored = 0, in_solid = 0, at_start = 0;
    for (size_t i = 0; i < n; ++i) {
      const float t0 = std::max(tmin[i % beams.size()], beams.range_min);
      if (clear[i]) {
        ++scored;
        same += (std::isinf(rb[i]) && std::isinf(re[i])) || std::abs(rb[i] - re[i]) <= 1e-3f;
      } else if (!solid[i]) {
        ++in_solid;
        at_start += rb[i] == t0 || std::isinf(rb[i]) || (max_range && rb[i] == tmax[i % beams.size()]);
      }
    }
    EXPECT_GT(scored, n / 2);
    EXPECT_GE(double(same), 0.999 * double(scored)) << same << " of " << scored;
    EXPECT_GT(in_solid, 100u);
    EXPECT_EQ(at_start, in_solid);
  }
}

}  // namespace polyloc::t_raycast_bsp
