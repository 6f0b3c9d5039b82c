// The Embree ray caster over numpy: explicit rays, scans (poses x beams), free-space queries.
// Results are written straight into the arrays returned; the GIL is released while casting.
#include "common.hpp"

#include <polyloc/raycast/embree.hpp>
#include <polyloc/sensors/sensor.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <memory>

namespace polyloc::py {

namespace raycast_impl {  // named, not anonymous: the module is compiled in batches (unity build)

// Output arrays for `shape` rays; normals are written SoA into a (3, ...) array and handed out
// as its transpose, an (..., 3) view.
struct Hits {
  pb::array_t<float> range;
  pb::array_t<uint32_t> triangle, label;
  pb::array_t<float> normal;
  HitBuffers buffers;

  Hits(std::vector<pb::ssize_t> shape, bool full) : range(shape) {
    buffers.range = range.mutable_data();
    if (!full) return;
    triangle = pb::array_t<uint32_t>(shape), label = pb::array_t<uint32_t>(shape);
    std::vector<pb::ssize_t> nshape{3};
    nshape.insert(nshape.end(), shape.begin(), shape.end());
    normal = pb::array_t<float>(nshape);
    const size_t n = static_cast<size_t>(range.size());
    buffers.triangle = triangle.mutable_data(), buffers.label = label.mutable_data();
    buffers.nx = normal.mutable_data(), buffers.ny = buffers.nx + n, buffers.nz = buffers.ny + n;
  }
  pb::object result(bool full) const {
    if (!full) return range;
    pb::dict d;
    d["range"] = range, d["triangle"] = triangle, d["label"] = label, d["normal"] = normal.attr("T");
    return d;
  }
};

// A scalar or an (N,) array as N values.
std::vector<float> perRay(const pb::handle& v, size_t n, const char* name) {
  if (const pb::array a = pb::array::ensure(v); a && a.ndim() == 0) {
    const F32Array s = floatArray(a, name, {});
    return std::vector<float>(n, *s.data());
  }
  const F32Array a = floatArray(v, name, {static_cast<pb::ssize_t>(n)});
  return {a.data(), a.data() + n};
}

pb::object cast(const EmbreeCaster& caster, const pb::handle& origins, const pb::handle& directions, const pb::handle& tmin,
                const pb::handle& tmax, bool full) {
  const F32Array d = floatArray(directions, "directions", {-1, 3});
  const size_t n = static_cast<size_t>(d.shape(0));
  const bool one_origin = pb::array::ensure(origins) && pb::array::ensure(origins).ndim() == 1;
  const F32Array o = one_origin ? floatArray(origins, "origins", {3}) : floatArray(origins, "origins", {static_cast<pb::ssize_t>(n), 3});
  std::vector<float> ox(n), oy(n), oz(n), dx(n), dy(n), dz(n);
  for (size_t i = 0; i < n; ++i) {
    const float* p = o.data() + (one_origin ? 0 : 3 * i);
    ox[i] = p[0], oy[i] = p[1], oz[i] = p[2];
    dx[i] = d.data()[3 * i], dy[i] = d.data()[3 * i + 1], dz[i] = d.data()[3 * i + 2];
    const float len = std::sqrt(dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i]);
    if (!(std::abs(len - 1.f) < 1e-3f))
      raise(PyExc_ValueError, fmt::format("directions: row {} has length {} (must be unit vectors)", i, len));
  }
  std::vector<float> t0 = perRay(tmin, n, "tmin"), t1 = perRay(tmax, n, "tmax");
  Hits hits({static_cast<pb::ssize_t>(n)}, full);
  RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t0.data(), t1.data(), n};
  {
    pb::gil_scoped_release nogil;
    caster.castRays(rays, hits.buffers);
  }
  return hits.result(full);
}

pb::object castScans(const EmbreeCaster& caster, const pb::handle& poses, const BeamSet& beams, const pb::handle& window_min,
                     const pb::handle& window_max, bool full) {
  const std::vector<Pose> p = toPoses(poses, "sensor_poses");
  const auto nb = static_cast<pb::ssize_t>(beams.size());
  F32Array w0, w1;
  ScanWindow window;
  if (!window_min.is_none()) w0 = floatArray(window_min, "window_min", {nb}), window.tmin = w0.data();
  if (!window_max.is_none()) w1 = floatArray(window_max, "window_max", {nb}), window.tmax = w1.data();
  Hits hits({static_cast<pb::ssize_t>(p.size()), nb}, full);
  {
    pb::gil_scoped_release nogil;
    caster.castScans(p, beams, hits.buffers, window);
  }
  return hits.result(full);
}

}  // namespace raycast_impl

void bindRaycast(pb::module_& m) {
  using namespace raycast_impl;
  pb::class_<EmbreeCaster, std::shared_ptr<EmbreeCaster>>(m, "EmbreeCaster", R"(Batch ray casting against a Mesh with Embree 3.

Ranges are metres along unit directions; a miss is +inf (or the window end with
miss_is_max_range). A ray that starts inside a closed solid (its first surface is a back face)
has range equal to its window start when backface_is_solid is set (the default). The caster keeps
its own copy of the mesh. Casting releases the GIL and runs on `threads` threads (0: all cores).)")
      .def(pb::init([](const Mesh& mesh, int threads, bool robust, bool high_quality_bvh) {
  using namespace raycast_impl;
             EmbreeOptions o;
             o.threads = threads, o.robust = robust, o.high_quality_bvh = high_quality_bvh;
             pb::gil_scoped_release nogil;
             return std::make_shared<EmbreeCaster>(mesh, o);
           }),
           pb::arg("mesh"), pb::arg("threads") = 0, pb::arg("robust") = true, pb::arg("high_quality_bvh") = true)
      .def_property("threads", &EmbreeCaster::threads, &EmbreeCaster::setThreads)
      .def_property_readonly("name", &EmbreeCaster::name)
      .def_property("backface_is_solid", [](const EmbreeCaster& c) { return c.options.backface_is_solid; },
                    [](EmbreeCaster& c, bool v) { c.options.backface_is_solid = v; })
      .def_property("miss_is_max_range", [](const EmbreeCaster& c) { return c.options.miss_is_max_range; },
                    [](EmbreeCaster& c, bool v) { c.options.miss_is_max_range = v; })
      .def("cast", &cast, pb::arg("origins"), pb::arg("directions"), pb::arg("tmin") = 0.0,
           pb::arg("tmax") = std::numeric_limits<double>::infinity(), pb::arg("hits") = false,
           R"(Cast N explicit rays.

origins: (N, 3), or (3,) for one origin of every ray; directions: (N, 3) unit vectors (ValueError
otherwise); tmin, tmax: scalars or (N,) arrays, the window each ray looks in. Returns ranges (N,)
float32, or with hits=True a dict of range, triangle (uint32, 0xFFFFFFFF for a miss), label
(uint32, 0 for a miss) and normal ((N, 3) float32, map frame).)")
      .def("cast_scans", &castScans, pb::arg("sensor_poses"), pb::arg("beams"), pb::arg("window_min") = pb::none(),
           pb::arg("window_max") = pb::none(), pb::arg("hits") = false,
           R"(Cast every beam of `beams` from every pose: ranges (P, B) float32 (or a dict with hits=True).

sensor_poses: map_T_sensor as a Pose, a list of them or a (P, 4, 4) array. Rays look in the beams'
[range_min, range_max], narrowed per beam by window_min / window_max ((B,) arrays) when given.)")
      .def("scan", [](const EmbreeCaster& c, const Sensor& s, const pb::handle& base_poses, bool hits) {
  using namespace raycast_impl;
        std::vector<Pose> p = toPoses(base_poses, "map_T_base");
        pb::list world;
        for (const Pose& q : p) world.append(pb::cast(s.worldPose(q)));
        return castScans(c, world, s.beams(), pb::none(), pb::none(), hits);
      }, pb::arg("sensor"), pb::arg("map_T_base"), pb::arg("hits") = false,
           "The exact scans of a mounted sensor on a robot at map_T_base (one pose or many): (P, B) float32.")
      .def("query_free", [](const EmbreeCaster& c, const pb::handle& points, float clearance) {
        const F32Array p = floatArray(points, "points", {-1, 3});
        const size_t n = static_cast<size_t>(p.shape(0));
        std::vector<Eigen::Vector3f> pts(n);
        for (size_t i = 0; i < n; ++i) pts[i] = Eigen::Vector3f(p.data()[3 * i], p.data()[3 * i + 1], p.data()[3 * i + 2]);
        pb::array_t<uint8_t> free(static_cast<pb::ssize_t>(n));
        {
          pb::gil_scoped_release nogil;
          c.queryFree(pts, clearance, free.mutable_data());
        }
        return free.attr("astype")("bool");
      }, pb::arg("points"), pb::arg("clearance") = 0.f,
           "(N,) bool: the point is outside every solid and at least `clearance` m from every surface.");
}

}  // namespace polyloc::py
