// Polygon maps: Mesh over numpy (views, no copies), load/save, validation report, slices.
#include "common.hpp"

#include <polyloc/map/load.hpp>
#include <polyloc/map/slice.hpp>
#include <polyloc/map/validate.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

#include <memory>

namespace polyloc::py {

namespace map_impl {  // named, not anonymous: the module is compiled in batches (unity build)

pb::array_t<float> boxArray(const Eigen::AlignedBox3f& b) {
  pb::array_t<float> a({2, 3});
  float* d = a.mutable_data();
  for (int i = 0; i < 3; ++i) d[i] = b.min()[i], d[3 + i] = b.max()[i];
  return a;
}

// A mesh from arrays: vertices (N, 3), triangles (M, 3) indices into them, labels (M,) indices
// into label_names ("" first, for unlabelled, unless given).
std::shared_ptr<Mesh> meshFromArrays(const pb::handle& vertices, const pb::handle& triangles, const pb::handle& labels,
                                     std::vector<std::string> label_names) {
  const F32Array v = floatArray(vertices, "vertices", {-1, 3});
  const auto t = pb::array_t<int64_t, pb::array::c_style | pb::array::forcecast>::ensure(triangles);
  if (!t || t.ndim() != 2 || t.shape(1) != 3)
    raise(PyExc_ValueError, "triangles: expected an (M, 3) array of vertex indices");
  auto mesh = std::make_shared<Mesh>();
  if (!label_names.empty()) mesh->label_names = std::move(label_names);
  const size_t nv = static_cast<size_t>(v.shape(0)), nt = static_cast<size_t>(t.shape(0));
  for (size_t i = 0; i < nv; ++i) {
    const Eigen::Vector3f p(v.data()[3 * i], v.data()[3 * i + 1], v.data()[3 * i + 2]);
    if (!p.allFinite()) raise(PyExc_ValueError, fmt::format("vertices: row {} is not finite", i));
    mesh->vertices.push_back(p);
  }
  for (size_t i = 0; i < nt; ++i) {
    Triangle tri;
    for (int k = 0; k < 3; ++k) {
      const int64_t idx = t.data()[3 * i + k];
      if (idx < 0 || static_cast<size_t>(idx) >= nv)
        raise(PyExc_ValueError, fmt::format("triangles: row {} refers to vertex {}, the mesh has {}", i, idx, nv));
      tri[k] = static_cast<uint32_t>(idx);
    }
    mesh->triangles.push_back(tri);
  }
  mesh->triangle_label.assign(nt, 0);
  if (!labels.is_none()) {
    const auto l = pb::array_t<int64_t, pb::array::c_style | pb::array::forcecast>::ensure(labels);
    if (!l || l.ndim() != 1 || static_cast<size_t>(l.shape(0)) != nt)
      raise(PyExc_ValueError, fmt::format("labels: expected ({},) label indices, one per triangle", nt));
    for (size_t i = 0; i < nt; ++i) {
      const int64_t id = l.data()[i];
      if (id < 0 || static_cast<size_t>(id) >= mesh->label_names.size())
        raise(PyExc_ValueError, fmt::format("labels: entry {} is {}, there are {} label names", i, id, mesh->label_names.size()));
      mesh->triangle_label[i] = static_cast<uint32_t>(id);
    }
  }
  mesh->source = "<arrays>";
  return mesh;
}

}  // namespace map_impl

void bindMap(pb::module_& m) {
  using namespace map_impl;
  pb::class_<Mesh, std::shared_ptr<Mesh>>(m, "Mesh", R"(A polygon map: indexed triangles in the map frame (z up, metres) with a label per triangle.

vertices, triangles and labels are read-only numpy views of the mesh's own memory (no copy).
Solids are closed and their triangles wind counter-clockwise seen from outside.)")
      .def(pb::init(&meshFromArrays), pb::arg("vertices"), pb::arg("triangles"), pb::arg("labels") = pb::none(),
           pb::arg("label_names") = std::vector<std::string>{},
           "Mesh from arrays: vertices (N, 3), triangles (M, 3) vertex indices, labels (M,) indices into\n"
           "label_names (default: all 0, with label_names [''], i.e. unlabelled).")
      .def_property_readonly("vertices", [](pb::object self) {
  using namespace map_impl;
        const Mesh& mesh = self.cast<const Mesh&>();
        return view<float>(mesh.vertices.empty() ? nullptr : mesh.vertices[0].data(),
                           {static_cast<pb::ssize_t>(mesh.vertices.size()), 3}, self);
      }, "(N, 3) float32, read-only view")
      .def_property_readonly("triangles", [](pb::object self) {
        const Mesh& mesh = self.cast<const Mesh&>();
        return view<uint32_t>(mesh.triangles.empty() ? nullptr : mesh.triangles[0].data(),
                              {static_cast<pb::ssize_t>(mesh.triangles.size()), 3}, self);
      }, "(M, 3) uint32 vertex indices, read-only view")
      .def_property_readonly("labels", [](pb::object self) {
        const Mesh& mesh = self.cast<const Mesh&>();
        return view<uint32_t>(mesh.triangle_label.data(), {static_cast<pb::ssize_t>(mesh.triangle_label.size())}, self);
      }, "(M,) uint32: per triangle an index into label_names, read-only view")
      .def_readonly("label_names", &Mesh::label_names, "label names; 0 is '' (unlabelled)")
      .def_readonly("source", &Mesh::source, "the file it was loaded from")
      .def_property_readonly("num_triangles", &Mesh::numTriangles)
      .def_property_readonly("num_vertices", &Mesh::numVertices)
      .def_property_readonly("bounds", [](const Mesh& mesh) { return boxArray(mesh.bounds()); },
                             "(2, 3) float32: min and max corner")
      .def("label_of", [](const Mesh& mesh, size_t tri) {
        if (tri >= mesh.numTriangles()) throw std::out_of_range(fmt::format("triangle {} of {}", tri, mesh.numTriangles()));
        return mesh.labelOf(tri);
      }, pb::arg("triangle"), "label name of a triangle")
      .def("find_label", &Mesh::findLabel, pb::arg("name"), "index of a label name, or -1")
      .def("normals", [](const Mesh& mesh) {
        pb::array_t<float> a({static_cast<pb::ssize_t>(mesh.numTriangles()), pb::ssize_t{3}});
        float* d = a.mutable_data();
        for (size_t i = 0; i < mesh.numTriangles(); ++i) {
          const Eigen::Vector3f n = mesh.triangleNormal(i);
          d[3 * i] = n.x(), d[3 * i + 1] = n.y(), d[3 * i + 2] = n.z();
        }
        return a;
      }, "(M, 3) float32 unit normals (right-hand rule), zero for degenerate triangles")
      .def("__len__", &Mesh::numTriangles)
      .def("__repr__", [](const Mesh& mesh) {
        return fmt::format("<polyloc.Mesh '{}': {} vertices, {} triangles, {} labels>", mesh.source, mesh.numVertices(),
                           mesh.numTriangles(), mesh.label_names.size());
      });

  m.def("load_mesh", [](const std::string& path, double scale, const std::string& up_axis, bool merge_vertices) {
    requireExists(path, "load_mesh");
    if (!(scale > 0)) raise(PyExc_ValueError, fmt::format("load_mesh: scale must be positive, got {}", scale));
    LoadOptions o;
    o.scale = scale;
    o.up_axis = parseUpAxis(up_axis);
    o.merge_vertices = merge_vertices;
    pb::gil_scoped_release nogil;
    return std::make_shared<Mesh>(loadMesh(path, o));
  }, pb::arg("path"), pb::arg("scale") = 1.0, pb::arg("up_axis") = "auto", pb::arg("merge_vertices") = true,
        R"(Load a polygon map with assimp (OBJ, PLY, STL, glTF/GLB, DAE, ...).

scale multiplies coordinates (0.001 for a CAD file in mm); up_axis is 'auto' (glTF: y, DAE: its
<up_axis>, others z), 'z', 'y' or 'x'. Labels come from object, mesh or material names.
Raises FileNotFoundError for a missing file, MapError (an OSError) for a file that cannot be
read or holds no triangles, ValueError for a bad scale.)");
  m.def("save_mesh", [](const Mesh& mesh, const std::string& path) {
    pb::gil_scoped_release nogil;
    saveMesh(mesh, path);
  }, pb::arg("mesh"), pb::arg("path"), "Write by extension (.obj+.mtl, .ply, .stl, .gltf, .glb, .dae); labels survive OBJ, glTF, DAE.");

  pb::class_<ValidationReport>(m, "ValidationReport", "What map validation found (validate_mesh).")
      .def_readonly("triangles", &ValidationReport::triangles)
      .def_readonly("vertices", &ValidationReport::vertices)
      .def_readonly("open_edges", &ValidationReport::open_edges, "edges of one triangle only (holes, borders)")
      .def_readonly("non_manifold_edges", &ValidationReport::non_manifold_edges, "edges of three or more triangles")
      .def_readonly("inconsistent_edges", &ValidationReport::inconsistent_edges, "shared edges with flipped winding")
      .def_readonly("degenerate_triangles", &ValidationReport::degenerate_triangles)
      .def_property_readonly("bounds", [](const ValidationReport& r) { return boxArray(r.bounds); })
      .def_property_readonly("label_counts", [](const ValidationReport& r) {
        pb::dict d;
        for (const auto& [name, count] : r.label_counts) d[pb::str(name)] = count;
        return d;
      }, "label -> triangle count")
      .def_property_readonly("closed", &ValidationReport::closed)
      .def_property_readonly("consistent_winding", &ValidationReport::consistentWinding)
      .def("summary", &ValidationReport::summary)
      .def("__repr__", &ValidationReport::summary);
  m.def("validate_mesh", [](const Mesh& mesh, float area_eps) {
    pb::gil_scoped_release nogil;
    return validateMesh(mesh, area_eps);
  }, pb::arg("mesh"), pb::arg("area_eps") = 1e-10f, "Open, non-manifold and inconsistent edges, degenerate triangles, labels.");

  m.def("slice_mesh", [](const Mesh& mesh, float height) {
    const std::vector<SliceSegment> segs = sliceMesh(mesh, height);
    const auto n = static_cast<pb::ssize_t>(segs.size());
    pb::array_t<float> a({n, pb::ssize_t{2}}), b({n, pb::ssize_t{2}});
    pb::array_t<uint32_t> tri(n), label(n);
    for (pb::ssize_t i = 0; i < n; ++i) {
      const SliceSegment& s = segs[i];
      a.mutable_at(i, 0) = s.a.x(), a.mutable_at(i, 1) = s.a.y();
      b.mutable_at(i, 0) = s.b.x(), b.mutable_at(i, 1) = s.b.y();
      tri.mutable_at(i) = s.triangle, label.mutable_at(i) = s.label;
    }
    pb::dict d;
    d["a"] = a, d["b"] = b, d["triangle"] = tri, d["label"] = label;
    return d;
  }, pb::arg("mesh"), pb::arg("height"),
        "Segments where triangles cross z = height: dict of a (K, 2), b (K, 2) float32, triangle and label (K,) uint32.");
}

}  // namespace polyloc::py
