// The procedural map generator: solids closed and outward, the lab's promised features where the
// docs say they are, the office's triangle budget, and committed maps that match the generator.
#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>
#include <polyloc/mapgen/builder.hpp>
#include <polyloc/mapgen/generate.hpp>
#include <polyloc/mapgen/walls.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <tuple>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mapgen {

using namespace polyloc;
using mapgen::MeshBuilder;
using V2 = Eigen::Vector2f;
using V3 = Eigen::Vector3f;


constexpr float kPi = static_cast<float>(M_PI);

// Joins vertices at identical positions across solids, as a loader that merges vertices does,
// so that solids sharing a vertex position would show up as non-manifold edges.
Mesh weld(const Mesh& in) {
  Mesh out = in;
  std::map<std::tuple<float, float, float>, uint32_t> ids;
  std::vector<uint32_t> remap(in.vertices.size());
  out.vertices.clear();
  for (size_t i = 0; i < in.vertices.size(); ++i) {
    const V3& v = in.vertices[i];
    auto [it, added] = ids.try_emplace({v.x(), v.y(), v.z()}, uint32_t(out.vertices.size()));
    if (added) out.vertices.push_back(v);
    remap[i] = it->second;
  }
  for (Triangle& t : out.triangles)
    for (uint32_t& v : t) v = remap[v];
  return out;
}

void expectClosedOutward(const Mesh& m, const std::string& what) {
  const ValidationReport r = validateMesh(m);
  EXPECT_EQ(r.open_edges, 0u) << what;
  EXPECT_EQ(r.non_manifold_edges, 0u) << what;
  EXPECT_EQ(r.inconsistent_edges, 0u) << what;
  EXPECT_EQ(r.degenerate_triangles, 0u) << what;
  EXPECT_GT(mapgen::signedVolume(m), 0.0) << what;
}

// Distance to the first triangle hit (optionally only those passing `accept`), or infinity.
float cast(const Mesh& m, const V3& o, const V3& dir,
           const std::function<bool(size_t)>& accept = nullptr, size_t* hit = nullptr) {
  const Eigen::Vector3d d = dir.normalized().cast<double>(), od = o.cast<double>();
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    if (accept && !accept(i)) continue;
    const Eigen::Vector3d a = m.vertices[m.triangles[i][0]].cast<double>();
    const Eigen::Vector3d e1 = m.vertices[m.triangles[i][1]].cast<double>() - a;
    const Eigen::Vector3d e2 = m.vertices[m.triangles[i][2]].cast<double>() - a;
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-12) continue;
    const Eigen::Vector3d s = od - a;
    const double u = s.dot(p) / det;
    if (u < 0 || u > 1) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    const double t = e2.dot(q) / det;
    if (t > 1e-6 && t < best) {
      best = t;
      if (hit) *hit = i;
    }
  }
  return static_cast<float>(best);
}

float centroidZ(const Mesh& m, size_t tri) {
  const Triangle& t = m.triangles[tri];
  return (m.vertices[t[0]].z() + m.vertices[t[1]].z() + m.vertices[t[2]].z()) / 3.f;
}

const Mesh& lab(MapLayout* layout = nullptr) {
  static MapLayout l;
  static const Mesh m = generateLab({}, &l);
  if (layout) *layout = l;
  return m;
}

const Mesh& office() {
  static const Mesh m = generateOffice();
  return m;
}


TEST(MapGenBuilder, BoxIsClosedOutwardWithItsVolume) {
  Mesh m;
  MeshBuilder(m).box({1, 2, 3}, {3, 5, 7}, "wall");
  EXPECT_EQ(m.numTriangles(), 12u);
  EXPECT_EQ(m.numVertices(), 8u);
  expectClosedOutward(m, "box");
  EXPECT_NEAR(mapgen::signedVolume(m), 2.0 * 3.0 * 4.0, 1e-4);
  for (size_t t = 0; t < m.numTriangles(); ++t) {  // every normal points away from the centre
    const Triangle& tr = m.triangles[t];
    const V3 c = (m.vertices[tr[0]] + m.vertices[tr[1]] + m.vertices[tr[2]]) / 3.f;
    EXPECT_GT(m.triangleNormal(t).dot(c - V3(2, 3.5f, 5)), 0.f);
  }
}

TEST(MapGenBuilder, EverySolidIsClosedAndOutward) {
  auto one = [](const std::function<void(MeshBuilder&)>& f, double volume, const char* what) {
    Mesh m;
    MeshBuilder b(m);
    f(b);
    expectClosedOutward(m, what);
    EXPECT_NEAR(mapgen::signedVolume(m), volume, 1e-3 * volume) << what;
  };
  one([](MeshBuilder& b) { b.orientedBox({4, -2}, {2, 0.5f}, 0.7f, 0.f, 3.f, "x"); }, 3.0, "rotated box");
  one([](MeshBuilder& b) {  // a frame turned by 90 degrees and raised
    b.pushFrame({10, 5}, kPi / 2, 0.3f);
    b.box({0, 0, 0}, {1, 2, 3}, "x");
    b.popFrame();
  }, 6.0, "box in a frame");
  // L-shaped (non-convex) footprint: 2x2 minus 1x1.
  one([](MeshBuilder& b) { b.prism({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0, 2, "x"); },
      6.0, "L prism");
  one([](MeshBuilder& b) { b.prism({{0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}, {0, 0}}, 0, 1, "x"); },
      3.0, "clockwise L prism");
  const int n = 24;
  one([&](MeshBuilder& b) { b.cylinder({1, 1}, 0.5f, 0, 2, n, "x"); },
      0.5 * n * 0.25 * std::sin(2 * M_PI / n) * 2, "cylinder");
  one([](MeshBuilder& b) { b.ramp({0, 0}, {5, 2}, 0, 0, 0.3f, "x"); }, 0.5 * 5 * 0.3 * 2, "wedge");
  // Sloped slab: 0.2 .. 0.5 above its base, 0.35 on average.
  one([](MeshBuilder& b) { b.ramp({0, 0}, {5, 2}, -0.2f, 0, 0.3f, "x"); }, 0.35 * 5 * 2,
      "sloped slab");
  // 4 steps of 0.2 down (tops -0.2..-0.8) over a base at -1: heights above base 0.8..0.2.
  one([](MeshBuilder& b) { b.stairs(0, 0, 1, 0, 4, -0.2f, 0.3f, -1, "x"); },
      0.3 * (0.8 + 0.6 + 0.4 + 0.2), "stairs down");
  one([](MeshBuilder& b) { b.stairs(0, 0, 1, 0, 3, 0.2f, 0.3f, 0, "x"); },
      0.3 * (0.2 + 0.4 + 0.6), "stairs up");
  one([](MeshBuilder& b) { b.slabWithHole({0, 0}, {4, 3}, {1, 1}, {2, 2.5f}, -0.2f, 0, "x"); },
      (12 - 1.5) * 0.2, "slab with hole");
}

TEST(MapGenBuilder, WallWithDoorIsBoxesThatShareNoVertex) {
  Mesh m;
  MeshBuilder b(m);
  mapgen::WallPlan plan;
  plan.addWall({0, 0}, {5, 0});
  plan.addWall({0, 0}, {0, 4});
  plan.addOpening({2, 0}, 0.8f, 2.0f);
  plan.build(b);
  EXPECT_EQ(m.numTriangles(), 4u * 12u);  // two pieces, a lintel, the other wall
  expectClosedOutward(weld(m), "walls welded");
  EXPECT_NEAR(cast(m, {2, 0, 1}, {1, 0, 0}), 0.4f, 1e-4);
  EXPECT_NEAR(cast(m, {2, 0, 1}, {-1, 0, 0}), 0.4f, 1e-4);
  EXPECT_NEAR(cast(m, {2, 0, 1}, {0, 0, 1}), 1.0f, 1e-4);
  EXPECT_THROW(
      {
        mapgen::WallPlan p;
        p.addWall({0, 0}, {5, 0});
        p.addOpening({2, 1}, 0.8f, 2.0f);
        p.build(b);
      },
      std::invalid_argument);
}

TEST(MapGenLab, HasEveryLabel) {
  const Mesh& m = lab();
  std::map<std::string, size_t> count;
  for (size_t t = 0; t < m.numTriangles(); ++t) count[m.labelOf(t)]++;
  for (const char* label : {"floor", "wall", "glass", "door", "table", "chair", "shelf", "cabinet",
                            "bin", "danger", "ramp"})
    EXPECT_GT(count[label], 0u) << label;
  EXPECT_EQ(count[""], 0u) << "unlabelled triangles";
  const Eigen::AlignedBox3f b = m.bounds();
  EXPECT_GE(b.sizes().x(), 20.f);
  EXPECT_LE(b.sizes().x(), 30.f);
  EXPECT_GE(b.sizes().y(), 12.f);
  EXPECT_LE(b.sizes().y(), 20.f);
  EXPECT_LE(b.max().z(), 3.0f);  // no ceiling above the walls
}

TEST(MapGenLab, SolidsAreClosedAndShareNoVertex) {
  expectClosedOutward(lab(), "lab");
  expectClosedOutward(weld(lab()), "lab welded");
}

TEST(MapGenLab, TableTopsAndChairSeatsAtTheirHeights) {
  MapLayout layout;
  const Mesh& m = lab(&layout);
  const int64_t table = m.findLabel("table"), chair = m.findLabel("chair");
  size_t tops = 0, seats = 0;
  for (size_t t = 0; t < m.numTriangles(); ++t) {
    if (m.triangleNormal(t).z() < 0.99f) continue;
    const float z = centroidZ(m, t);
    if (m.triangle_label[t] == table) {
      EXPECT_NEAR(z, 0.75f, 0.02f);
      ++tops;
    }
    if (m.triangle_label[t] == chair && z > 0.3f && z < 0.55f) {  // seat band (not base, back)
      EXPECT_NEAR(z, 0.45f, 0.02f);
      ++seats;
    }
  }
  EXPECT_GT(tops, 0u);
  EXPECT_GT(seats, 0u);
  ASSERT_GE(layout.tables.size(), 3u);
  ASSERT_GE(layout.chairs.size(), 3u);
  for (const V2& p : layout.tables) {
    size_t hit;
    EXPECT_NEAR(3.f - cast(m, {p.x(), p.y(), 3.f}, {0, 0, -1}, nullptr, &hit), 0.75f, 1e-3);
    EXPECT_EQ(m.labelOf(hit), "table");
  }
  for (const V2& p : layout.chairs) {
    size_t hit;
    EXPECT_NEAR(3.f - cast(m, {p.x(), p.y(), 3.f}, {0, 0, -1}, nullptr, &hit), 0.45f, 1e-3);
    EXPECT_EQ(m.labelOf(hit), "chair");
  }
}

TEST(MapGenLab, RampHasSixPercentGrade) {
  MapLayout layout;
  const Mesh& m = lab(&layout);
  const int64_t ramp = m.findLabel("ramp");
  size_t up = 0;
  for (size_t t = 0; t < m.numTriangles(); ++t) {
    if (m.triangle_label[t] != ramp || m.triangleNormal(t).z() < 0.5f) continue;
    EXPECT_NEAR(std::acos(m.triangleNormal(t).z()), std::atan(0.06f), 0.01f);
    ++up;
  }
  EXPECT_GT(up, 0u);
  ASSERT_EQ(layout.ramps.size(), 1u);
  ASSERT_EQ(layout.platforms.size(), 1u);
  const V2 mid = layout.ramps[0].center();  // halfway up: 0.15 m
  EXPECT_NEAR(3.f - cast(m, {mid.x(), mid.y(), 3.f}, {0, 0, -1}), 0.15f, 1e-3);
  const V2 top = layout.platforms[0].center();
  EXPECT_NEAR(3.f - cast(m, {top.x(), top.y(), 3.f}, {0, 0, -1}), 0.3f, 1e-3);
}

TEST(MapGenLab, DoorOpeningsAreThreeQuarterMetreWide) {
  MapLayout layout;
  const Mesh& m = lab(&layout);
  const int64_t wall = m.findLabel("wall");
  auto wall_only = [&](size_t t) { return m.triangle_label[t] == wall; };
  size_t lab_doors = 0;
  for (const DoorInfo& d : layout.doors) {
    const V3 c(d.centre.x(), d.centre.y(), d.floor_z + 1.0f), u(d.along.x(), d.along.y(), 0);
    EXPECT_NEAR(cast(m, c, u, wall_only) + cast(m, c, -u, wall_only), d.width, 1e-3) << d.name;
    EXPECT_NEAR(cast(m, c, {0, 0, 1}, wall_only), d.height - 1.0f, 1e-3) << d.name;
    if (d.name.rfind("lab", 0) == 0) {
      EXPECT_NEAR(d.width, 0.75f, 1e-6);
      EXPECT_NEAR(cast(m, c, u, wall_only), 0.375f, 1e-3) << d.name;
      EXPECT_FALSE(d.closed);
      ++lab_doors;
    }
  }
  EXPECT_EQ(lab_doors, 3u);
}

TEST(MapGenLab, StairwellGoesDownAndIsDanger) {
  MapLayout layout;
  const Mesh& m = lab(&layout);
  ASSERT_EQ(layout.stairwells.size(), 1u);
  const Eigen::AlignedBox2f s = layout.stairwells[0];
  size_t hit;
  // One tread in, the first step is one riser (3/17 m) down.
  const float d = cast(m, {s.min().x() + 0.5f, s.min().y() + 0.14f, 2.f}, {0, 0, -1}, nullptr, &hit);
  EXPECT_NEAR(2.f - d, -3.f / 17.f, 1e-3);
  EXPECT_EQ(m.labelOf(hit), "danger");
  const float bottom = cast(m, {s.center().x(), s.max().y() - 0.3f, 2.f}, {0, 0, -1}, nullptr, &hit);
  EXPECT_NEAR(2.f - bottom, -3.f, 1e-3);
  EXPECT_EQ(m.labelOf(hit), "danger");
}

TEST(MapGenOffice, BenchmarkSizeClosedAndDoors) {
  const Mesh& m = office();
  EXPECT_GE(m.numTriangles(), 9000u);
  EXPECT_LE(m.numTriangles(), 11000u);
  expectClosedOutward(weld(m), "office welded");
  MapLayout layout;
  const Mesh m2 = generateOffice({}, &layout);
  EXPECT_EQ(layout.doors.size(), 24u);
  const int64_t wall = m2.findLabel("wall");
  for (const DoorInfo& d : layout.doors) {
    const V3 c(d.centre.x(), d.centre.y(), 1.f), u(d.along.x(), d.along.y(), 0);
    auto w = [&](size_t t) { return m2.triangle_label[t] == wall; };
    EXPECT_NEAR(cast(m2, c, u, w) + cast(m2, c, -u, w), 0.9f, 1e-3) << d.name;
  }
  EXPECT_THROW(generateOffice({.rows = 0}), std::invalid_argument);
}

TEST(MapGenMaps, DeterministicAndNamed) {
  const Mesh a = generateMap("lab"), b = generateMap("lab");
  ASSERT_EQ(a.numVertices(), b.numVertices());
  EXPECT_TRUE(a.vertices == b.vertices);
  EXPECT_TRUE(a.triangles == b.triangles);
  EXPECT_EQ(generateMap("office").numTriangles(), office().numTriangles());
  try {
    generateMap("garage");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown map 'garage': expected lab or office");
  }
}

// maps/lab.obj and maps/office.obj are committed; regenerate them with
// `polyloc map generate NAME --out maps/NAME.obj` when the generator changes.
TEST(MapGenMaps, CommittedFilesMatchTheGenerator) {
  for (const std::string name : {"lab", "office"}) {
    const Mesh gen = generateMap(name);
    const Mesh file = loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/" + name + ".obj");
    EXPECT_EQ(file.numTriangles(), gen.numTriangles()) << name << ".obj is stale";
    const Eigen::AlignedBox3f bf = file.bounds(), bg = gen.bounds();
    EXPECT_LT((bf.min() - bg.min()).cwiseAbs().maxCoeff(), 1e-4f) << name;
    EXPECT_LT((bf.max() - bg.max()).cwiseAbs().maxCoeff(), 1e-4f) << name;
    std::map<std::string, size_t> cf, cg;
    for (size_t t = 0; t < file.numTriangles(); ++t) cf[file.labelOf(t)]++;
    for (size_t t = 0; t < gen.numTriangles(); ++t) cg[gen.labelOf(t)]++;
    EXPECT_EQ(cf, cg) << name << ": labels differ";
    const ValidationReport r = validateMesh(file);
    EXPECT_EQ(r.open_edges, 0u) << name;
    EXPECT_EQ(r.non_manifold_edges, 0u) << name;
    EXPECT_EQ(r.inconsistent_edges, 0u) << name;
  }
}

}  // namespace polyloc::t_mapgen
