// validateMesh: edge topology of a cube and of the ways a cube goes wrong, degenerate triangles,
// bounds, label counts and the summary text.
#include <polyloc/map/validate.hpp>

#include <gtest/gtest.h>

#include <chrono>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_map_validate {

using namespace polyloc;


// Unit cube [0,1]^3: corner i is (i&1, i>>1&1, i>>2&1); faces counter-clockwise from outside.
Mesh unitCube() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const uint32_t side = m.labelId("wall");
  for (int f = 0; f < 6; ++f) {
    const auto* q = quads[f];
    const uint32_t label = f == 0 ? m.labelId("floor") : f == 1 ? m.labelId("ceiling") : side;
    m.triangles.push_back({uint32_t(q[0]), uint32_t(q[1]), uint32_t(q[2])});
    m.triangles.push_back({uint32_t(q[0]), uint32_t(q[2]), uint32_t(q[3])});
    m.triangle_label.insert(m.triangle_label.end(), 2, label);
  }
  return m;
}


TEST(MapValidate, ClosedCubeIsClean) {
  const Mesh cube = unitCube();
  for (size_t t = 0; t < cube.numTriangles(); ++t) {  // the fixture itself: normals point out
    const Eigen::Vector3f centre =
        (cube.vertices[cube.triangles[t][0]] + cube.vertices[cube.triangles[t][1]] +
         cube.vertices[cube.triangles[t][2]]) /
        3.f;
    EXPECT_GT(cube.triangleNormal(t).dot(centre - Eigen::Vector3f(0.5f, 0.5f, 0.5f)), 0.f) << t;
  }
  const ValidationReport r = validateMesh(cube);
  EXPECT_EQ(r.triangles, 12u);
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.open_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.consistentWinding());
  EXPECT_TRUE(r.bounds.min().isApprox(Eigen::Vector3f(0, 0, 0)));
  EXPECT_TRUE(r.bounds.max().isApprox(Eigen::Vector3f(1, 1, 1)));
}

TEST(MapValidate, RemovedTriangleLeavesThreeOpenEdges) {
  Mesh cube = unitCube();
  cube.triangles.erase(cube.triangles.begin() + 5);
  cube.triangle_label.erase(cube.triangle_label.begin() + 5);
  const ValidationReport r = validateMesh(cube);
  EXPECT_EQ(r.open_edges, 3u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_FALSE(r.closed());
  EXPECT_TRUE(r.consistentWinding());
}

TEST(MapValidate, FlippedTriangleGivesThreeInconsistentEdges) {
  Mesh cube = unitCube();
  std::swap(cube.triangles[7][1], cube.triangles[7][2]);
  const ValidationReport r = validateMesh(cube);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_EQ(r.open_edges, 0u);
  EXPECT_TRUE(r.closed());
  EXPECT_FALSE(r.consistentWinding());
}

TEST(MapValidate, ThirdTriangleOnAnEdgeIsNonManifold) {
  Mesh cube = unitCube();
  // A fin on the bottom edge (0,1): three triangles share it now.
  cube.vertices.emplace_back(0.5f, -1.f, 0.f);
  cube.triangles.push_back({0, 1, 8});
  cube.triangle_label.push_back(0);
  const ValidationReport r = validateMesh(cube);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.open_edges, 2u);  // the fin's two free edges
  EXPECT_FALSE(r.closed());
}

TEST(MapValidate, DegenerateTriangles) {
  Mesh cube = unitCube();
  cube.triangles.push_back({0, 0, 1});  // repeated index
  cube.vertices.emplace_back(2.f, 0.f, 0.f);
  cube.triangles.push_back({0, 1, 8});     // collinear: zero area
  cube.triangles.push_back({0, 1, 1000});  // index out of range: counted, does not crash
  cube.triangle_label.insert(cube.triangle_label.end(), 3, 0);
  const ValidationReport r = validateMesh(cube);
  EXPECT_EQ(r.degenerate_triangles, 3u);
  // The collinear sliver still takes part in the topology; the other two do not.
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.open_edges, 2u);
  // A bigger area threshold makes every cube triangle (area 0.5) degenerate.
  EXPECT_EQ(validateMesh(unitCube(), 0.6f).degenerate_triangles, 12u);
}

TEST(MapValidate, BoundsLabelsAndSummary) {
  Mesh cube = unitCube();
  for (auto& v : cube.vertices)
    v = v.cwiseProduct(Eigen::Vector3f(4, 3, 2.5f)) + Eigen::Vector3f(-2, 10, 0);
  cube.labelId("unused");  // a label without triangles is not listed
  const ValidationReport r = validateMesh(cube);
  EXPECT_TRUE(r.bounds.min().isApprox(Eigen::Vector3f(-2, 10, 0)));
  EXPECT_TRUE(r.bounds.max().isApprox(Eigen::Vector3f(2, 13, 2.5f)));
  const std::vector<std::pair<std::string, size_t>> expected = {
      {"ceiling", 2}, {"floor", 2}, {"wall", 8}};
  EXPECT_EQ(r.label_counts, expected);

  const std::string s = r.summary();
  EXPECT_NE(s.find("triangles: 12\n"), std::string::npos) << s;
  EXPECT_NE(s.find("vertices: 8\n"), std::string::npos) << s;
  EXPECT_NE(s.find("bounds: [-2.000, 10.000, 0.000] .. [2.000, 13.000, 2.500] m"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("open edges: 0\n"), std::string::npos) << s;
  EXPECT_NE(s.find("non-manifold edges: 0\n"), std::string::npos) << s;
  EXPECT_NE(s.find("inconsistent edges: 0\n"), std::string::npos) << s;
  EXPECT_NE(s.find("degenerate triangles: 0\n"), std::string::npos) << s;
  EXPECT_NE(s.find("  wall: 8\n"), std::string::npos) << s;
  EXPECT_LT(s.find("ceiling"), s.find("floor")) << s;
}

TEST(MapValidate, UnlabelledAndEmptyMesh) {
  Mesh m;
  const ValidationReport empty = validateMesh(m);
  EXPECT_EQ(empty.triangles, 0u);
  EXPECT_NE(empty.summary().find("bounds: empty"), std::string::npos);

  m.addTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0);
  const ValidationReport r = validateMesh(m);
  ASSERT_EQ(r.label_counts.size(), 1u);
  EXPECT_EQ(r.label_counts[0], std::make_pair(std::string(), size_t{1}));
  EXPECT_NE(r.summary().find("(unlabelled): 1"), std::string::npos);
  EXPECT_EQ(r.open_edges, 3u);
}

// A height field of a million triangles: border edges are open, the rest shared once each way.
TEST(MapValidate, MillionTriangleGrid) {
  const uint32_t n = 708;  // 2 * 708^2 = 1'002'528 triangles
  Mesh m;
  m.vertices.reserve((n + 1) * (n + 1));
  for (uint32_t y = 0; y <= n; ++y)
    for (uint32_t x = 0; x <= n; ++x)
      m.vertices.emplace_back(x * 0.1f, y * 0.1f, 0.01f * ((x * y) % 7));
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 2, d = a + n + 1;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  m.triangle_label.assign(m.triangles.size(), 0);
  const auto start = std::chrono::steady_clock::now();
  const ValidationReport r = validateMesh(m);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("validate_seconds", std::to_string(seconds));
  EXPECT_EQ(r.triangles, 2u * n * n);
  EXPECT_EQ(r.open_edges, 4u * n);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_LT(seconds, 10.0);  // generous: ~0.3 s in Release; catches an accidental O(n^2)
}

}  // namespace polyloc::t_map_validate
