// The GPU ray caster (raycast/gpu.hpp) on whatever EGL offers (Mesa llvmpipe in CI), beyond the
// contract of every caster (test_raycast_conformance.cpp): the BVH holds every triangle once;
// ranges agree with Embree's within 1 mm on >= 99.9% of random, windowed, grazing and edge rays
// of the lab, misses too; labels and normals follow; bad rays miss; the beam model summed on the
// GPU equals the CPU's; a filter weighing on the GPU tracks; and every error path.
#ifdef POLYLOC_HAVE_GPU
#include <polyloc/gpu/bvh.hpp>
#include <polyloc/raycast/gpu.hpp>
#include <polyloc/config/yaml.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/config_yaml.hpp>
#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/factory.hpp>
#include <polyloc/raycast/workload.hpp>

#include "mcl_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <thread>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_gpu {

using namespace polyloc;
using namespace polyloc::test;


const Mesh& lab() {
  static const Mesh m = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  return m;
}

// Rays of four kinds over the map: random origins and directions (a third with a random window),
// rays aimed at triangle edges and vertices, and rays grazing a triangle's plane.
struct Rays {
  std::vector<float> ox, oy, oz, dx, dy, dz, t0, t1;
  void add(const Eigen::Vector3f& o, Eigen::Vector3f d, float a, float b) {
    d.normalize();
    ox.push_back(o.x()), oy.push_back(o.y()), oz.push_back(o.z());
    dx.push_back(d.x()), dy.push_back(d.y()), dz.push_back(d.z());
    t0.push_back(a), t1.push_back(b);
  }
  RayBatch batch() const {
    return {ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t0.data(), t1.data(), ox.size()};
  }
};

Rays conformanceRays(const Mesh& mesh, size_t per_kind) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  const Eigen::AlignedBox3f box = mesh.bounds();
  const Eigen::Vector3f lo = box.min(), hi = box.max();
  auto inside = [&] { return Eigen::Vector3f(lo.x() + u(rng) * (hi - lo).x(), lo.y() + u(rng) * (hi - lo).y(), lo.z() + u(rng) * (hi - lo).z()); };
  auto dir = [&] { return Eigen::Vector3f(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f); };
  auto vertex = [&](size_t t, int k) { return mesh.vertices[mesh.triangles[t][k]]; };
  std::uniform_int_distribution<size_t> tri(0, mesh.triangles.size() - 1);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  Rays r;
  for (size_t i = 0; i < per_kind; ++i) {
    const float a = 3.f * u(rng);
    r.add(inside(), dir(), i % 3 == 0 ? a : 0.f, i % 3 == 0 ? a + 2.f * u(rng) : kInf);
  }
  for (size_t i = 0; i < per_kind; ++i) {  // at an edge point or a vertex
    const size_t t = tri(rng);
    const int k = int(i % 3);
    const Eigen::Vector3f target = i % 2 ? vertex(t, k) : (vertex(t, k) + vertex(t, (k + 1) % 3)) * 0.5f;
    const Eigen::Vector3f o = inside();
    r.add(o, target - o, 0.f, kInf);
  }
  for (size_t i = 0; i < per_kind; ++i) {  // nearly in a triangle's plane, from 0.5-3 m away
    const size_t t = tri(rng);
    const Eigen::Vector3f n = mesh.triangleNormal(t);
    if (n.isZero()) continue;
    const Eigen::Vector3f c = (vertex(t, 0) + vertex(t, 1) + vertex(t, 2)) / 3.f;
    Eigen::Vector3f along = n.cross(dir()).normalized();
    const Eigen::Vector3f d = (along + n * (0.02f * (u(rng) - 0.5f))).normalized();
    r.add(c - d * (0.5f + 2.5f * u(rng)) + n * 1e-3f * (u(rng) - 0.5f), d, 0.f, kInf);
  }
  return r;
}

struct Compare {
  size_t rays = 0, agree = 0, miss_disagree = 0;
};

Compare compare(const float* a, const float* b, size_t n, float tol = 1e-3f) {
  Compare c;
  c.rays = n;
  for (size_t i = 0; i < n; ++i) {
    const bool ha = std::isfinite(a[i]), hb = std::isfinite(b[i]);
    if (ha != hb) ++c.miss_disagree;
    else if (!ha || std::abs(a[i] - b[i]) <= tol) ++c.agree;
  }
  return c;
}


TEST(GpuBvh, HoldsEveryTriangleOnceInsideItsBoxes) {
  const Mesh& m = lab();
  const GpuBvh bvh = buildGpuBvh(m);
  size_t with_area = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) with_area += !m.triangleNormal(t).isZero();
  ASSERT_EQ(bvh.triangle.size(), with_area);
  EXPECT_EQ(std::set<uint32_t>(bvh.triangle.begin(), bvh.triangle.end()).size(), with_area);
  EXPECT_EQ(bvh.vertices.size(), 12 * with_area);
  std::printf("[gpu] BVH of the lab: %zu triangles, depth %d\n", with_area, int(bvh.depth));
  // Measured 20 (binned SAH, leaves of 4: log2(6758 / 4) = 11 at best); 48 was the builder's own
  // cap, a bound that could not fail. A 1.5x deeper tree (30) fails.
  EXPECT_LE(bvh.depth, 24);
  // Every triangle lies in the box its parent keeps for its leaf, every inner child's boxes in
  // the box its parent keeps for it; every triangle is reached once.
  std::vector<int> reached(bvh.triangle.size(), 0);
  std::function<void(int32_t, const float*, const float*)> walk = [&](int32_t ref, const float* lo, const float* hi) {
    if (ref < 0) {
      const uint32_t k = uint32_t(-ref - 1), first = k >> 4, count = k & 15;
      ASSERT_GE(count, 1u);
      for (uint32_t i = first; i < first + count; ++i) {
        ++reached[i];
        for (int v = 0; v < 3; ++v)
          for (int c = 0; c < 3; ++c) {
            ASSERT_GE(bvh.vertices[12 * i + 4 * v + c], lo[c]);
            ASSERT_LE(bvh.vertices[12 * i + 4 * v + c], hi[c]);
          }
      }
      return;
    }
    const GpuBvhNode& n = bvh.nodes[size_t(ref)];
    for (int c = 0; c < 3; ++c) {
      ASSERT_GE(n.lmin[c], lo[c]);
      ASSERT_LE(n.lmax[c], hi[c]);
      ASSERT_GE(n.rmin[c], lo[c]);
      ASSERT_LE(n.rmax[c], hi[c]);
    }
    walk(n.left, n.lmin, n.lmax);
    walk(n.right, n.rmin, n.rmax);
  };
  const float inf[3] = {1e30f, 1e30f, 1e30f}, minf[3] = {-1e30f, -1e30f, -1e30f};
  walk(0, minf, inf);
  EXPECT_EQ(std::count(reached.begin(), reached.end(), 1), long(reached.size()));
  // One triangle: the root is its leaf, twice.
  const GpuBvh one = buildGpuBvh(boxRoom(1.f, 1.f, 1.f, 0.1f), 15);
  EXPECT_GE(one.nodes.size(), 1u);
  EXPECT_THROW(buildGpuBvh(Mesh{}), std::invalid_argument);
}

// Where a front and a back face meet at an edge or vertex, a ray through that point meets both at
// one distance and which one counts is a convention: Embree keeps whichever its traversal met
// last, the GPU the front face (the ray touched the surface; the origin is not inside a solid).
// Those rays are "facing ties": the same surface at the same distance (the ranges agree with
// backface_is_solid off), one backend reporting the window start. They are counted apart.
TEST(GpuCaster, AgreesWithEmbreeOnRandomEdgeAndGrazingRays) {
  EmbreeCaster embree(lab());
  GpuCaster gpu(lab());
  const size_t per_kind = 20000;
  const Rays r = conformanceRays(lab(), per_kind);
  const size_t n = r.ox.size();
  std::vector<float> a(n), b(n), a_raw(n), b_raw(n);
  std::vector<uint32_t> la(n), lb(n), ta(n), tb(n);
  std::vector<float> nxa(n), nya(n), nza(n), nxb(n), nyb(n), nzb(n);
  gpu.castRays(r.batch(), {a.data(), ta.data(), la.data(), nxa.data(), nya.data(), nza.data()});
  embree.castRays(r.batch(), {b.data(), tb.data(), lb.data(), nxb.data(), nyb.data(), nzb.data()});
  gpu.options.backface_is_solid = embree.options.backface_is_solid = false;
  gpu.castRays(r.batch(), {a_raw.data()});
  embree.castRays(r.batch(), {b_raw.data()});
  const char* kinds[] = {"random (a third windowed)", "at edges and vertices", "grazing"};
  size_t agree_all = 0, ties_all = 0, miss_all = 0;
  for (size_t kind = 0; kind < 3; ++kind) {
    const size_t k0 = kind * per_kind, k1 = std::min(n, k0 + per_kind);
    const Compare c = compare(a.data() + k0, b.data() + k0, k1 - k0);
    const Compare raw = compare(a_raw.data() + k0, b_raw.data() + k0, k1 - k0);
    size_t ties = 0;
    for (size_t i = k0; i < k1; ++i) {
      const bool strict = std::isfinite(a[i]) == std::isfinite(b[i]) && (!std::isfinite(a[i]) || std::abs(a[i] - b[i]) <= 1e-3f);
      ties += !strict && std::isfinite(a_raw[i]) && std::isfinite(b_raw[i]) && std::abs(a_raw[i] - b_raw[i]) <= 1e-3f &&
              (a[i] != a_raw[i] || b[i] != b_raw[i]);
    }
    std::printf("[gpu] %s: %zu rays, %.3f%% within 1 mm of Embree, %.3f%% more facing ties, %zu hit/miss disagreements "
                "(backface_is_solid off: %.3f%%)\n", kinds[kind], k1 - k0, 100.0 * double(c.agree) / double(k1 - k0),
                100.0 * double(ties) / double(k1 - k0), c.miss_disagree, 100.0 * double(raw.agree) / double(k1 - k0));
    // Measured 99.80 / 98.85 / 98.87% strict; with facing ties 100 / 99.67 / 100% (the rest: rays
    // through a silhouette vertex, which a last-bit change in the direction flips in either).
    EXPECT_GE(double(c.agree), (kind == 0 ? 0.997 : 0.983) * double(k1 - k0)) << kinds[kind];
    EXPECT_GE(double(c.agree + ties), (kind == 1 ? 0.996 : 0.9995) * double(k1 - k0)) << kinds[kind];
    agree_all += c.agree, ties_all += ties, miss_all += c.miss_disagree;
  }
  EXPECT_GE(double(agree_all + ties_all), 0.998 * double(n));  // measured 99.89%
  EXPECT_LE(double(miss_all), 0.001 * double(n));
  // Same triangle: same label and normal; a miss: none.
  size_t same = 0;
  for (size_t i = 0; i < n; ++i) {
    if (ta[i] == kNoHit) {
      EXPECT_EQ(la[i], 0u);
      EXPECT_EQ(nxa[i], 0.f);
      continue;
    }
    if (ta[i] != tb[i]) continue;
    ++same;
    ASSERT_EQ(la[i], lb[i]);
    ASSERT_EQ(nxa[i], nxb[i]);
    ASSERT_EQ(nza[i], nzb[i]);
  }
  EXPECT_GT(same, n / 2);
}

TEST(GpuCaster, WindowedScansAgreeWithEmbree) {
  EmbreeCaster embree(lab());
  GpuCaster gpu(lab());
  const std::vector<Pose> poses = randomPlanarPoses(lab().bounds(), 300, 0.3, 3);
  const BeamSet beams = horizontalFan(181, 20.f);
  std::vector<float> full(poses.size() * beams.size());
  embree.castScans(poses, beams, {full.data()});
  // Windows around the first pose's ranges (a beam model's), so most rays of other poses miss.
  std::vector<float> t0(beams.size()), t1(beams.size());
  for (size_t b = 0; b < beams.size(); ++b) {
    const float z = std::isfinite(full[b]) ? full[b] : 5.f;
    t0[b] = std::max(0.f, z - 0.3f), t1[b] = z + 0.3f;
  }
  for (const bool max_range : {false, true}) {
    std::vector<float> a(full.size()), b(full.size());
    gpu.options.miss_is_max_range = embree.options.miss_is_max_range = max_range;
    gpu.castScans(poses, beams, {a.data()}, {t0.data(), t1.data()});
    embree.castScans(poses, beams, {b.data()}, {t0.data(), t1.data()});
    const Compare c = compare(a.data(), b.data(), a.size());
    EXPECT_GE(double(c.agree), 0.999 * double(a.size())) << "miss_is_max_range " << max_range;
    EXPECT_EQ(a[0], b[0]);
  }
}

TEST(GpuCaster, BadRaysAndPosesMissWithoutHarm) {
  const GpuCaster gpu(boxRoom(2.f, 1.5f, 3.f, 0.2f));
  const float nan = std::nanf(""), big = 1e19f;
  const std::vector<float> ox{0, big, nan, 0}, oy{0, 0, 0, 0}, oz{0.3f, 0.3f, 0.3f, 0.3f};
  const std::vector<float> dx{1, 1, 1, 1}, dy{0, 0, 0, 0}, dz{0, 0, 0, 0}, t0{0, 0, 0, nan}, t1{10, 10, 10, 10};
  std::vector<float> r(4, -1.f);
  gpu.castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t0.data(), t1.data(), 4}, {r.data()});
  EXPECT_NEAR(r[0], 2.f, 1e-5f);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(r[size_t(i)], std::numeric_limits<float>::infinity()) << i;
  const std::vector<Pose> poses{Pose::planar(0, 0, 0), Pose::planar(1e19, 0, 0), Pose::planar(nan, 0, 0)};
  const BeamSet beams = horizontalFan(3, 10.f);
  std::vector<float> s(9);
  gpu.castScans(poses, beams, {s.data()});
  EXPECT_TRUE(std::isfinite(s[1]));
  for (size_t i = 3; i < 9; ++i) EXPECT_EQ(s[i], std::numeric_limits<float>::infinity()) << i;
  const std::vector<Eigen::Vector3f> points{{0, 0, 1}, {big, 0, 1}, {nan, 0, 1}};
  uint8_t f[3] = {7, 7, 7};
  gpu.queryFree(points, 0.2f, f);
  EXPECT_EQ(f[0], 1);
  EXPECT_EQ(f[1], 0);
  EXPECT_EQ(f[2], 0);
}

// The beam model weighed with the GPU's per-pose sums equals the CPU's within float precision,
// except for particles with a ray whose window starts where two of the room's wall slabs touch
// (coplanar faces whose distances differ in the last bit: the backends may keep different faces,
// test AgreesWithEmbreeOnRandomEdgeAndGrazingRays): 12 of the 2000 particles here.
size_t differing(const std::vector<double>& a, const std::vector<double>& b, double* worst_agreeing) {
  size_t n = 0;
  *worst_agreeing = 0;
  for (size_t p = 0; p < a.size(); ++p) {
    const double rel = std::abs(a[p] - b[p]) / std::max(1.0, std::abs(a[p]));
    if (rel > 2e-5) ++n;
    else *worst_agreeing = std::max(*worst_agreeing, rel);
  }
  return n;
}

TEST(GpuCaster, BeamWeighingEqualsTheCpuModel) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster embree(mesh);
  GpuCaster gpu(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg;
  cfg.beams_per_scan = 60;
  const Pose truth = Pose::planar(-1.0, 0.4, 0.3);
  std::vector<Pose> poses;
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 0.3);
  for (int i = 0; i < 2000; ++i) poses.push_back(Pose::planar(truth.x() + g(rng), truth.y() + g(rng), truth.yaw() + g(rng)));
  const ParticleSet ps = particlesAt(poses);
  const std::vector<float> scan = simulateScan(embree, rig.sensors[0], truth, 0.01, 1);
  for (const bool coarse : {false, true}) {
    SensorFrame f;
    f.ranges = scan;
    f.coarse = coarse;
    BeamSensorModel cpu_model(embree, rig, cfg), gpu_model(gpu, rig, cfg);
    std::vector<double> a(poses.size(), 0.0), b(poses.size(), 0.0);
    ASSERT_EQ(cpu_model.weigh(ps, f, a), gpu_model.weigh(ps, f, b));
    double worst = 0;
    const size_t diff = differing(a, b, &worst);
    std::printf("[gpu] beam weighing, coarse %d: %zu of %zu particles differ (a facing tie), the others within %.2e\n",
                int(coarse), diff, a.size(), worst);
    EXPECT_LE(diff, a.size() / 100);  // measured 12 of 2000
    // The ranking of the particles is the CPU's: the best is the same.
    EXPECT_EQ(std::max_element(a.begin(), a.end()) - a.begin(), std::max_element(b.begin(), b.end()) - b.begin());
  }
  // Range-dependent sigma (no table), as the depth model weighs.
  BeamSensorModel cpu_model(embree, rig, cfg), gpu_model(gpu, rig, cfg);
  const std::vector<size_t> sel = BeamSensorModel::selectBeams(rig.sensors[0].beams(), scan, 50);
  SensorFrame f;
  f.ranges = scan;
  std::vector<double> a(poses.size(), 0.0), b(poses.size(), 0.0);
  cpu_model.weighSelected(ps, f, sel, 0.01, a);
  gpu_model.weighSelected(ps, f, sel, 0.01, b);
  double worst = 0;
  EXPECT_LE(differing(a, b, &worst), a.size() / 100);
}

// mcl.caster: gpu: the filter weighs on the GPU (the floor and free space stay on Embree) and
// tracks the loop of the asymmetric room as the Embree filter does.
TEST(GpuCaster, FilterWeighingOnTheGpuTracks) {
  const LoopRun r = trackLoopWeighingOn("gpu");
  EXPECT_EQ(r.weighed_by, "gpu");
  // Measured 0.9 mm / 0.003 deg on Mesa's llvmpipe (the Embree filter's figures): 1.5x worse fails.
  EXPECT_LT(r.pos_err, 0.0014);
  EXPECT_LT(r.yaw_err_deg, 0.01);
  EXPECT_EQ(r.estimate.status, MclStatus::Tracking);
  EXPECT_GT(r.estimate.updates, 40u);
}

// Casters share EGL's display: one going does not end another's; any thread may call one.
TEST(GpuCaster, CastersComeAndGoAndServeAnyThread) {
  const Mesh room = boxRoom(2.f, 1.5f, 3.f, 0.2f);
  const GpuCaster a(room);
  const Eigen::Vector3f o(0.12f, 0.07f, 0.3f), d(1, 0, 0);
  const RayBatch ray{&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), nullptr, nullptr, 1};
  {
    const GpuCaster b(room);
    float r = 0;
    b.castRays(ray, {&r});
    EXPECT_NEAR(r, 1.88f, 1e-4f);
  }
  std::vector<float> got(4, 0.f);
  std::vector<std::thread> threads;
  for (size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] {
      for (int k = 0; k < 20; ++k) a.castRays(ray, {&got[i]});
    });
  for (auto& t : threads) t.join();
  for (float r : got) EXPECT_NEAR(r, 1.88f, 1e-4f);
}

// Was: every batch ended with no context current, unbinding a caller's own GL context.
TEST(GpuCaster, LeavesTheCallersContextCurrent) {
  const Mesh room = boxRoom(2.f, 1.5f, 3.f, 0.2f);
  GpuContext mine;
  mine.makeCurrent();
  {
    const GpuCaster c(room);  // builds, casts and is destroyed with its own context
    const Eigen::Vector3f o(0.12f, 0.07f, 0.3f), d(1, 0, 0);
    float r = 0;
    c.castRays({&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), nullptr, nullptr, 1}, {&r});
    EXPECT_NEAR(r, 1.88f, 1e-4f);
    EXPECT_TRUE(mine.current());
  }
  EXPECT_TRUE(mine.current());
  mine.release();
  EXPECT_FALSE(mine.current());
}

TEST(GpuCaster, ErrorsNameWhatIsMissing) {
  const Mesh room = boxRoom(2.f, 1.5f, 3.f, 0.2f);
  GpuCasterOptions bad;
  bad.context.platforms = "nonsense";
  try {
    GpuCaster g(room, bad);
    FAIL() << "no error for an unknown platform";
  } catch (const GpuError& e) {
    EXPECT_NE(std::string(e.what()).find("nonsense"), std::string::npos) << e.what();
  }
  // A buffer over the GPU's largest storage block: the error says so, with the sizes.
  GpuCasterOptions huge;
  huge.batch_rays = size_t(1) << 40;
  const GpuCaster g(room, huge);
  const std::vector<Pose> many(size_t(1) << 20, Pose::planar(0, 0, 0));
  const BeamSet beams = horizontalFan(64, 10.f);
  std::vector<float> out(many.size() * beams.size());
  try {
    g.castScans(many, beams, {out.data()});
    FAIL() << "no error for a batch over the largest storage block";
  } catch (const GpuError& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the largest storage block"), std::string::npos) << e.what();
  }
  // A lost context: an error, and the next batch is an error too (never a silent wrong answer).
  GpuCasterOptions lost;
  lost.fail_batch = 0;
  const GpuCaster l(room, lost);
  float r = 0;
  const Eigen::Vector3f o(0, 0, 0.3f), d(1, 0, 0);
  const RayBatch ray{&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), nullptr, nullptr, 1};
  EXPECT_THROW(l.castRays(ray, {&r}), GpuError);
  // Built without a GPU the factory names the option; here: an unknown platform is the error.
  CasterOptions co;
  co.gpu_platforms = "nonsense";
  EXPECT_THROW(makeCaster("gpu", room, co), GpuError);
}

TEST(GpuCaster, FallsBackToEmbreeWhenConfigured) {
  const Mesh room = boxRoom(2.f, 1.5f, 3.f, 0.2f);
  std::vector<std::string> warnings;
  CasterOptions co;
  co.gpu_platforms = "nonsense";
  co.gpu_fallback = true;
  co.warn = [&](const std::string& w) { warnings.push_back(w); };
  const auto c = makeCaster("gpu", room, co);
  EXPECT_STREQ(c->name(), "embree");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("nonsense"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("embree"), std::string::npos) << warnings[0];
  // A context lost while running: one warning, then Embree's answers, for this and later batches.
  GpuCasterOptions lost;
  lost.fail_batch = 1;
  lost.fallback = true;
  lost.warn = [&](const std::string& w) { warnings.push_back(w); };
  const GpuCaster g(room, lost);
  const Eigen::Vector3f o(0.12f, 0.07f, 0.3f), d(1, 0, 0);
  const RayBatch ray{&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), nullptr, nullptr, 1};
  for (int i = 0; i < 3; ++i) {
    float r = 0;
    g.castRays(ray, {&r});
    EXPECT_NEAR(r, 1.88f, 1e-4f) << "batch " << i;
    EXPECT_EQ(g.fellBack(), i >= 1);
  }
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[1].find("lost"), std::string::npos) << warnings[1];
}

TEST(GpuCaster, ConfigKeysAndChoices) {
  const Rig lisa = rigPreset("lisa");
  ConfigMap m = ConfigMap::parse("mcl:\n  caster: gpu\n  gpu_fallback: embree\n  gpu_platforms: device\n", "g.yaml");
  const MclConfig c = parseMclConfig(m.map("mcl"), &lisa);
  EXPECT_EQ(c.caster, "gpu");
  EXPECT_EQ(c.gpu_fallback, "embree");
  EXPECT_EQ(c.gpu_platforms, "device");
  ConfigMap bad = ConfigMap::parse("mcl:\n  gpu_fallback: cpu\n", "g.yaml");
  EXPECT_THROW(parseMclConfig(bad.map("mcl"), &lisa), ConfigError);
}
#endif

}  // namespace polyloc::t_raycast_gpu
