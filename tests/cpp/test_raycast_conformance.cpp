// Every ray caster that makeCaster knows (casterNames()) against one contract, with tolerances
// per backend: known ranges in the box room (planar, and 3D for the 3D backends), scans equal to
// rays, windows and misses, a window starting inside solid, free-space queries, the same answers
// on 1 and 2 threads, its memory, and agreement with Embree on the lab map. Backend-specific
// behaviour (BSP build, grid slices, octomap voxels, Embree's two paths) stays in
// test_raycast_<backend>.cpp.
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/factory.hpp>

#include "fixtures.hpp"
#include "raycast_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_conformance {

using namespace polyloc;
using polyloc::test::castOne;
using polyloc::test::freeAt;
using polyloc::test::kInfRange;


struct Contract {
  float tol;                 // m, range error on the box room's walls
  double resolution;         // m, cell / voxel / node size (CasterOptions)
  bool planar_only;          // grid2d: a slice, no floor or ceiling
  bool knows_interiors;      // octomap: interiors are unknown, not solid
  double lab_median, lab_p75, lab_hit_disagreement;  // agreement with Embree on the lab
};

// Tolerances from each representation: exact meshes to float precision; a grid or voxel map
// within one cell (a wall on a cell boundary may land in either); the distance field within half
// a node. Lab agreement: docs/benchmarks.md "Map representations" (medians are the resolution,
// tails are rays that pass within a cell of a chair leg).
Contract contractOf(const std::string& name) {
  if (name == "embree") return {1e-4f, 0.05, false, true, 0.0, 0.0, 0.0};
  if (name == "bsp") return {1e-4f, 0.05, false, true, 1e-3, 1e-3, 0.01};
  if (name == "grid2d") return {0.051f, 0.05, true, true, 0.05, 0.075, 0.03};
  if (name == "distance3d") return {0.026f, 0.05, false, true, 0.05, 0.15, 0.03};
  if (name == "octomap") return {0.051f, 0.05, false, false, 0.10, 0.20, 0.03};
  if (name == "gpu") return {1e-4f, 0.05, false, true, 1e-3, 1e-3, 0.001};  // float32 on a BVH
  ADD_FAILURE() << "no contract for the caster '" << name << "': add one here";
  return {};
}

std::unique_ptr<RayCaster> make(const std::string& name, const Mesh& mesh, int threads = 0, double resolution = 0) {
  CasterOptions o;
  o.threads = threads;
  o.resolution = resolution > 0 ? resolution : contractOf(name).resolution;
  o.height = 0.3;
  return makeCaster(name, mesh, o);
}

struct Conformance : ::testing::TestWithParam<std::string> {
  // Interior [-2, 2] x [-1.5, 1.5] x [0, 3]; walls, floor and ceiling 0.2 m thick.
  Mesh room = polyloc::test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  Contract c = contractOf(GetParam());
};


TEST_P(Conformance, KnownRangesInTheBoxRoom) {
  const auto caster = make(GetParam(), room);
  const Eigen::Vector3f o(0.12f, 0.07f, 0.3f);
  EXPECT_NEAR(castOne(*caster, o, {1, 0, 0}), 1.88f, c.tol);
  EXPECT_NEAR(castOne(*caster, o, {-1, 0, 0}), 2.12f, c.tol);
  EXPECT_NEAR(castOne(*caster, o, {0, 1, 0}), 1.43f, c.tol);
  EXPECT_NEAR(castOne(*caster, o, {0, -1, 0}), 1.57f, c.tol);
  const float cs = std::cos(0.5236f), sn = std::sin(0.5236f);
  EXPECT_NEAR(castOne(*caster, o, {cs, sn, 0}), 1.88f / cs, 2 * c.tol);  // the wall x = 2 at 30 deg
  // A scan from the same place gives what the rays give.
  const BeamSet beams = horizontalFan(4, 30.f);
  const Pose pose = Pose::fromXYZRPY(o.x(), o.y(), o.z(), 0, 0, 0);
  float r[4];
  caster->castScans(std::span<const Pose>(&pose, 1), beams, {r});
  EXPECT_NEAR(r[0], 1.88f, c.tol);
  EXPECT_NEAR(r[1], 1.43f, c.tol);
  if (c.planar_only) return;
  EXPECT_NEAR(castOne(*caster, o, {0, 0, 1}), 2.7f, c.tol);   // ceiling
  EXPECT_NEAR(castOne(*caster, o, {0, 0, -1}), 0.3f, c.tol);  // floor
  const Eigen::Vector3f d = Eigen::Vector3f(1, 0.3f, 0.2f).normalized();
  EXPECT_NEAR(castOne(*caster, o, d), 1.88f / d.x(), 2 * c.tol);
}

TEST_P(Conformance, WindowsMissesAndWindowsStartingInSolid) {
  const auto caster = make(GetParam(), room);
  const Eigen::Vector3f o(0, 0, 0.3f);
  EXPECT_EQ(castOne(*caster, o, {1, 0, 0}, 0.f, 1.f), kInfRange);   // the wall is beyond tmax
  EXPECT_EQ(castOne(*caster, o, {1, 0, 0}, 1.5f, 1.f), kInfRange);  // an empty window
  EXPECT_EQ(castOne(*caster, o, {1, 0, 0}, 2.5f, 10.f), kInfRange); // beyond the wall: nothing
  EXPECT_NEAR(castOne(*caster, o, {1, 0, 0}, 1.f, 10.f), 2.0f, c.tol);
  if (c.knows_interiors) {  // a window starting inside the wall: the start (backface_is_solid)
    EXPECT_NEAR(castOne(*caster, o, {1, 0, 0}, 2.1f, 10.f), 2.1f, 1e-5f);
  }
  caster->options.miss_is_max_range = true;
  EXPECT_FLOAT_EQ(castOne(*caster, o, {1, 0, 0}, 0.f, 1.f), 1.f);
}

TEST_P(Conformance, FreeSpaceAndClearance) {
  const auto caster = make(GetParam(), room);
  // At 1 m: the floor 1 m below, the ceiling 2 m above (grid2d: points off the slice count as it).
  EXPECT_TRUE(freeAt(*caster, {0, 0, 1.f}, 0.5f));
  EXPECT_FALSE(freeAt(*caster, {1.8f, 0, 1.f}, 0.3f));  // 0.2 m from the wall x = 2
  EXPECT_TRUE(freeAt(*caster, {1.6f, 0, 1.f}, 0.3f));   // 0.4 m from it
  if (c.knows_interiors) {
    EXPECT_FALSE(freeAt(*caster, {2.1f, 0, 1.f}, 0.f));  // inside the wall
  }
}

TEST_P(Conformance, SameAnswersOnOneAndTwoThreads) {
  const auto one = make(GetParam(), room, 1), two = make(GetParam(), room, 2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  const size_t n = 3000;
  std::vector<float> ox(n), oy(n), oz(n), dx(n), dy(n), dz(n), r1(n), r2(n);
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3f d(u(rng), u(rng), c.planar_only ? 0.f : u(rng));
    d.normalize();
    ox[i] = 1.5f * u(rng), oy[i] = u(rng), oz[i] = 0.3f, dx[i] = d.x(), dy[i] = d.y(), dz[i] = d.z();
  }
  const RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, n};
  one->castRays(rays, {r1.data()});
  two->castRays(rays, {r2.data()});
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(r1[i], r2[i]) << "ray " << i;
  EXPECT_EQ(one->threads(), 1);
  EXPECT_EQ(two->threads(), 2);
}

TEST_P(Conformance, ReportsItsMemory) {
  const auto caster = make(GetParam(), room);
  // The box room: a BSP of its merged faces needs under 1 KB, a 5 cm field or grid far more.
  EXPECT_GT(caster->memoryBytes(), 256u) << "a backend that says it holds nothing";
  EXPECT_LT(caster->memoryBytes(), size_t(1) << 30);
  if (GetParam() == "embree") {
    EXPECT_GT(caster->memoryBytes(), room.numTriangles() * 36) << "less than its copy of the mesh";
  }
}

TEST_P(Conformance, AgreesWithEmbreeOnTheLab) {
  const Mesh lab = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  // 10 cm for the fields and voxels: keeps the build short; the bounds are for that size.
  const double res = GetParam() == "grid2d" ? 0.05 : 0.1;
  const auto caster = make(GetParam(), lab, 0, res);
  const auto a = polyloc::test::agreeWithEmbree(*caster, lab, 200, 90, 0.3);
  EXPECT_GT(a.both_hit, 5000u);
  EXPECT_LE(a.median, c.lab_median);
  EXPECT_LE(a.p75, c.lab_p75);
  EXPECT_LE(a.hit_disagreement, c.lab_hit_disagreement);
}

INSTANTIATE_TEST_SUITE_P(AllCasters, Conformance, ::testing::ValuesIn(casterNames()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace polyloc::t_raycast_conformance
