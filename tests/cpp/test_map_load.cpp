// loadMesh / saveMesh: round trips through every writable format (coordinates, winding, labels),
// the label rule on hand-written OBJ files, node transforms, scale and up axis, and clear
// MapErrors for missing, empty and corrupt files.
#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>

#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <functional>
#include <iterator>

#include "temp_dir.hpp"

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_map_load {

using namespace polyloc;
using polyloc::test::TempDir;
using V3 = Eigen::Vector3f;


// A box [lo, hi] with outward counter-clockwise faces and labels floor, ceiling, door (one
// side), wall (two sides) and unlabelled (one side). Corner i picks hi on axis k if bit k is set.
Mesh labelledBox(const V3& lo, const V3& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const char* labels[6] = {"floor", "ceiling", "door", "wall", "wall", ""};
  for (int f = 0; f < 6; ++f) {
    const uint32_t label = m.labelId(labels[f]);
    const auto* q = quads[f];
    m.triangles.push_back({uint32_t(q[0]), uint32_t(q[1]), uint32_t(q[2])});
    m.triangles.push_back({uint32_t(q[0]), uint32_t(q[2]), uint32_t(q[3])});
    m.triangle_label.insert(m.triangle_label.end(), 2, label);
  }
  return m;
}

V3 centroid(const Mesh& m, size_t t) {
  return (m.vertices[m.triangles[t][0]] + m.vertices[m.triangles[t][1]] +
          m.vertices[m.triangles[t][2]]) /
         3.f;
}

// Every triangle's normal points away from the centre of the (convex) mesh.
void expectOutwardNormals(const Mesh& m) {
  const V3 centre = m.bounds().center();
  for (size_t t = 0; t < m.numTriangles(); ++t)
    EXPECT_GT(m.triangleNormal(t).dot(centroid(m, t) - centre), 0.f) << "triangle " << t;
}

// Index of the triangle in `in` with the same corners in the same cyclic order, or -1.
int findTriangle(const Mesh& in, const Mesh& m, size_t t, float tol) {
  for (size_t u = 0; u < in.numTriangles(); ++u)
    for (int shift = 0; shift < 3; ++shift) {
      bool same = true;
      for (int k = 0; k < 3 && same; ++k)
        same = (in.vertices[in.triangles[u][(k + shift) % 3]] - m.vertices[m.triangles[t][k]])
                   .cwiseAbs()
                   .maxCoeff() <= tol;
      if (same) return static_cast<int>(u);
    }
  return -1;
}

void expectThrowsWith(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no MapError thrown";
  } catch (const MapError& e) {
    const std::string what = e.what();
    for (const std::string& part : parts) EXPECT_NE(what.find(part), std::string::npos) << what;
  }
}


class MapRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(MapRoundTrip, KeepsCoordinatesWindingAndLabels) {
  const std::string ext = GetParam();
  const bool has_names = ext != "ply" && ext != "stl";
  TempDir dir;
  // Building-sized, off-origin coordinates that are not round numbers in binary.
  const Mesh box = labelledBox(V3(-12.345678f, 40.1f, -0.3f), V3(7.654321f, 52.9876f, 3.1415926f));
  const std::string path = dir.file("box." + ext);
  saveMesh(box, path);
  const Mesh m = loadMesh(path);
  EXPECT_EQ(m.source, path);
  ASSERT_EQ(m.numTriangles(), 12u);
  EXPECT_EQ(m.numVertices(), 8u);  // welded across the per-label objects
  EXPECT_LE((m.bounds().min() - box.bounds().min()).cwiseAbs().maxCoeff(), 1e-5f);
  EXPECT_LE((m.bounds().max() - box.bounds().max()).cwiseAbs().maxCoeff(), 1e-5f);
  std::vector<int> seen(12, 0);
  for (size_t t = 0; t < m.numTriangles(); ++t) {
    const int u = findTriangle(box, m, t, 1e-5f);
    ASSERT_GE(u, 0) << "triangle " << t << " not in the original (moved or flipped)";
    ++seen[u];
    EXPECT_EQ(m.labelOf(t), has_names ? box.labelOf(u) : "") << "triangle " << t;
  }
  EXPECT_EQ(seen, std::vector<int>(12, 1));
  const ValidationReport r = validateMesh(m);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.consistentWinding());
  expectOutwardNormals(m);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, MapRoundTrip,
                         ::testing::Values("obj", "ply", "stl", "gltf", "glb", "dae"),
                         [](const auto& info) { return info.param; });

TEST(MapLoad, WithoutMergingVerticesStlKeepsCornersApart) {
  TempDir dir;
  saveMesh(labelledBox(V3(0, 0, 0), V3(1, 1, 1)), dir.file("box.stl"));
  LoadOptions options;
  options.merge_vertices = false;
  const Mesh m = loadMesh(dir.file("box.stl"), options);
  EXPECT_EQ(m.numVertices(), 36u);
  EXPECT_EQ(validateMesh(m).open_edges, 36u);
}

// The label rule: the object or group name (o/g) wins, then the mesh name, then the material
// (usemtl); names are normalised ("door_1" -> "door") and assimp's made-up names are skipped.
TEST(MapLoad, ObjLabelsFromObjectsGroupsAndMaterials) {
  TempDir dir;
  const std::string path = dir.write("labels.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                                     "usemtl Glass.001\n"
                                     "f 1 2 3\n"  // no object: the material names it
                                     "o door_1\n"
                                     "usemtl wood\n"
                                     "f 1 3 4\n"  // object name beats material
                                     "o glass_front\n"
                                     "usemtl glass\n"
                                     "f 1 2 5\n"
                                     "usemtl wood\n"
                                     "f 2 3 5\n"  // still the object glass_front
                                     "g Wall-12\n"
                                     "f 3 4 5\n"  // groups name like objects
                                     "g\n"
                                     "usemtl DefaultMaterial\n"
                                     "f 4 1 5\n");  // nothing meaningful: unlabelled
  const Mesh m = loadMesh(path);
  ASSERT_EQ(m.numTriangles(), 6u);
  const std::vector<std::string> expected = {"glass",       "door", "glass_front",
                                             "glass_front", "wall", ""};
  // assimp reorders faces by object and material: find each hand-written face by its corners.
  std::vector<std::string> got;
  const std::vector<std::array<int, 3>> faces = {{1, 2, 3}, {1, 3, 4}, {1, 2, 5},
                                                 {2, 3, 5}, {3, 4, 5}, {4, 1, 5}};
  const V3 corner[6] = {V3(0, 0, 0) /* OBJ counts from 1 */,
                        V3(0, 0, 0),
                        V3(1, 0, 0),
                        V3(1, 1, 0),
                        V3(0, 1, 0),
                        V3(0, 0, 1)};
  for (const auto& f : faces) {
    Mesh one;
    one.addTriangle(corner[f[0]], corner[f[1]], corner[f[2]], 0);
    std::string label = "<missing>";
    for (size_t t = 0; t < m.numTriangles(); ++t)
      if (findTriangle(one, m, t, 0.f) == 0) label = m.labelOf(t);
    got.push_back(label);
  }
  EXPECT_EQ(got, expected);
}

// glTF: node transforms (translation, a mirroring scale) and instanced meshes; unnamed nodes
// ("nodes[0]") and meshes are no labels, a named node is.
TEST(MapLoad, GltfNodeTransformsAndMirroring) {
  TempDir dir;
  // One triangle (0,0,0) (1,0,0) (0,1,0), normal +z, used by three nodes.
  const std::string path = dir.write("nodes.gltf", R"({"asset":{"version":"2.0"},"scene":0,
    "scenes":[{"nodes":[0,1,2]}],
    "nodes":[{"mesh":0},{"mesh":0,"translation":[0,0,10]},{"mesh":0,"name":"Mirror_2","scale":[-1,1,1]}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
    "buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})");
  LoadOptions as_written;
  as_written.up_axis = UpAxis::Z;
  const Mesh m = loadMesh(path, as_written);
  ASSERT_EQ(m.numTriangles(), 3u);
  int plain = 0, lifted = 0, mirrored = 0;
  for (size_t t = 0; t < 3; ++t) {
    EXPECT_TRUE(m.triangleNormal(t).isApprox(V3(0, 0, 1))) << "winding kept, also when mirrored";
    const V3 c = centroid(m, t);
    const std::string& label = m.labelOf(t);
    if (c.isApprox(V3(1 / 3.f, 1 / 3.f, 0))) plain += label.empty();
    if (c.isApprox(V3(1 / 3.f, 1 / 3.f, 10))) lifted += label.empty();
    if (c.isApprox(V3(-1 / 3.f, 1 / 3.f, 0))) mirrored += label == "mirror";
  }
  EXPECT_EQ(plain, 1);
  EXPECT_EQ(lifted, 1);
  EXPECT_EQ(mirrored, 1);
  EXPECT_EQ(m.numVertices(), 7u);  // the plain and mirrored copies share two corners

  // By default a glTF is y up, as its spec says: the node lifted along file +z lands at map -y.
  const Mesh up = loadMesh(path);
  LoadOptions yup;
  yup.up_axis = UpAxis::Y;
  const Mesh y = loadMesh(path, yup);
  ASSERT_EQ(up.numVertices(), y.numVertices());
  for (size_t v = 0; v < up.numVertices(); ++v) EXPECT_TRUE(up.vertices[v].isApprox(y.vertices[v]));
  EXPECT_FLOAT_EQ(up.bounds().min().y(), -10.f);
}

TEST(MapLoad, ScaleAndUpAxis) {
  TempDir dir;
  // A 4 x 2.5 x 3 m box (3 m tall) written in millimetres with y up: a proper rotation,
  // map (x, y, z) = file (x, -z, y), so the file holds (x, z, -y) and its faces stay outward.
  Mesh yup = labelledBox(V3(0, 0, 0), V3(4000, 2500, 3000));
  for (auto& v : yup.vertices) v = V3(v.x(), v.z(), -v.y());
  saveMesh(yup, dir.file("yup.obj"));
  LoadOptions options;
  options.scale = 0.001;
  options.up_axis = UpAxis::Y;
  const Mesh m = loadMesh(dir.file("yup.obj"), options);
  EXPECT_TRUE(m.bounds().min().isApprox(V3(0, 0, 0), 1e-5f)) << m.bounds().min().transpose();
  EXPECT_LE((m.bounds().max() - V3(4, 2.5f, 3)).cwiseAbs().maxCoeff(), 1e-5f)
      << m.bounds().max().transpose();
  expectOutwardNormals(m);
  const int64_t ceiling = m.findLabel("ceiling");
  ASSERT_GE(ceiling, 0);
  for (size_t t = 0; t < m.numTriangles(); ++t) {
    if (m.triangle_label[t] == static_cast<uint32_t>(ceiling)) {
      EXPECT_TRUE(m.triangleNormal(t).isApprox(V3(0, 0, 1))) << "ceiling faces up";
    }
  }

  // One point through each axis convention, on a single triangle.
  dir.write("tri.obj", "v 1 2 3\nv 2 2 3\nv 1 3 3\nf 1 2 3\n");
  auto first = [&](UpAxis up) {
    LoadOptions o;
    o.up_axis = up;
    const Mesh t = loadMesh(dir.file("tri.obj"), o);
    return std::make_pair(t.vertices[t.triangles[0][0]], t.triangleNormal(0));
  };
  EXPECT_TRUE(first(UpAxis::Z).first.isApprox(V3(1, 2, 3)));
  EXPECT_TRUE(first(UpAxis::Y).first.isApprox(V3(1, -3, 2)));   // file +y is map +z
  EXPECT_TRUE(first(UpAxis::Y).second.isApprox(V3(0, -1, 0)));  // file +z normal -> map -y
  EXPECT_TRUE(first(UpAxis::X).first.isApprox(V3(-3, 2, 1)));   // file +x is map +z
  EXPECT_TRUE(first(UpAxis::X).second.isApprox(V3(-1, 0, 0)));
}

TEST(MapLoad, ParseUpAxis) {
  EXPECT_EQ(parseUpAxis("z"), UpAxis::Z);
  EXPECT_EQ(parseUpAxis("Auto"), UpAxis::Auto);
  EXPECT_EQ(parseUpAxis("Y"), UpAxis::Y);
  EXPECT_EQ(parseUpAxis("x"), UpAxis::X);
  expectThrowsWith([] { parseUpAxis("w"); }, {"'w'"});
}

TEST(MapLoad, ErrorsNameTheFileAndTheProblem) {
  TempDir dir;
  const std::string missing = dir.file("no_such_map.obj");
  expectThrowsWith([&] { loadMesh(missing); }, {missing, "does not exist"});
  const std::string zero = dir.write("zero.obj", "");
  expectThrowsWith([&] { loadMesh(zero); }, {zero, "empty"});
  std::string garbage(4096, '\0');
  for (size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<char>((i * 7919 + 13) % 251);
  const std::string ply = dir.write("garbage.ply", garbage);
  expectThrowsWith([&] { loadMesh(ply); }, {ply});
  const std::string bad_index = dir.write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
  expectThrowsWith([&] { loadMesh(bad_index); }, {bad_index});
  const std::string points = dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expectThrowsWith([&] { loadMesh(points); }, {points, "no triangles"});
  const std::string nan = dir.write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expectThrowsWith([&] { loadMesh(nan); }, {nan, "non-finite"});
  expectThrowsWith([&] { loadMesh(dir.file("nan.obj"), LoadOptions{0.0}); }, {"scale"});
  expectThrowsWith([&] { loadMesh(dir.file("")); }, {"not a regular file"});
  const std::string unknown = dir.file("box.xyz123");
  expectThrowsWith([&] { saveMesh(labelledBox(V3(0, 0, 0), V3(1, 1, 1)), unknown); },
                   {unknown, "extension"});
}

// assimp 5.2's PLY reader hangs on a header without end_header and reads past the end of, or
// aborts on, truncated and corrupt bodies; loadMesh must give an error for each instead.
TEST(MapLoad, CorruptPlyFailsCleanly) {
  TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n";
  const std::string cut =
      dir.write("cut_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  expectThrowsWith([&] { loadMesh(cut); }, {cut, "end_header"});
  const std::string ascii_cut =
      dir.write("ascii_cut.ply", header + "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0");
  expectThrowsWith([&] { loadMesh(ascii_cut); }, {ascii_cut, "truncated"});
  const std::string no_corners =
      dir.write("no_corners.ply", header + "end_header\n0 0 0\n1 0 0\n0 1 0\n0\n");
  expectThrowsWith([&] { loadMesh(no_corners); }, {no_corners, "no corners"});
  const std::string bad_index =
      dir.write("bad_index.ply", header + "end_header\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 7\n");
  expectThrowsWith([&] { loadMesh(bad_index); }, {bad_index, "vertex 7"});

  saveMesh(labelledBox(V3(0, 0, 0), V3(1, 1, 1)), dir.file("box.ply"));  // binary
  std::ifstream in(dir.file("box.ply"), std::ios::binary);
  const std::string full((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(loadMesh(dir.file("box.ply")).numTriangles(), 12u);
  for (size_t keep : {full.size() - 1, full.size() - 30, full.find("end_header") + 40}) {
    const std::string path = dir.write("box_cut.ply", full.substr(0, keep));
    expectThrowsWith([&] { loadMesh(path); }, {path, "truncated"});
  }
}

TEST(MapLoad, TruncatedFilesOfEveryFormatFailCleanly) {
  TempDir dir;
  for (const std::string ext : {"obj", "ply", "stl", "gltf", "glb", "dae"}) {
    const std::string path = dir.file("box." + ext);
    saveMesh(labelledBox(V3(0, 0, 0), V3(1, 1, 1)), path);
    std::ifstream in(path, std::ios::binary);
    const std::string full((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (size_t keep : {size_t{1}, full.size() / 3, full.size() / 2, full.size() - 2}) {
      const std::string cut = dir.write("cut." + ext, full.substr(0, keep));
      try {
        loadMesh(cut);  // some cuts still hold a (partial) mesh: fine, as long as nothing crashes
      } catch (const MapError& e) {
        EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
      }
    }
  }
}

}  // namespace polyloc::t_map_load
