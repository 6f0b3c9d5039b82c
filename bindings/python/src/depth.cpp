// ToF/PMD depth filtering over numpy images: the settings of every stage, the filter, and its
// result as (H, W) views (depth, valid, reason) plus the kept pixels as base-frame points.
#include "common.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/depth/config_yaml.hpp>
#include <polyloc/depth/filter.hpp>
#include <polyloc/sensors/sensor.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

namespace polyloc::py {

namespace depth_impl {  // named, not anonymous: the module is compiled in batches (unity build)

#define POLYLOC_RW(f) .def_readwrite(#f, &T::f)

void bindDepthConfig(pb::module_& m) {
  {
    using T = DepthValidity;
    pb::class_<T>(m, "DepthValidity", "validity: range (None: the camera's) and amplitude limits")
        .def(pb::init<>()) POLYLOC_RW(range_min) POLYLOC_RW(range_max) POLYLOC_RW(amplitude_min);
  }
  {
    using T = JumpEdgeFilter;
    pb::class_<T>(m, "JumpEdgeFilter", "jump_edge: flying pixels by the view-ray angle (min_angle in rad)")
        .def(pb::init<>()) POLYLOC_RW(enabled) POLYLOC_RW(min_angle) POLYLOC_RW(mode) POLYLOC_RW(neighbours);
  }
  {
    using T = ConfidenceFilter;
    pb::class_<T>(m, "ConfidenceFilter", "confidence: the thesis's eq. 6.4, iterated (docs/depth.md)")
        .def(pb::init<>()) POLYLOC_RW(enabled) POLYLOC_RW(prediction) POLYLOC_RW(iterations) POLYLOC_RW(reach)
            POLYLOC_RW(sigma) POLYLOC_RW(noise) POLYLOC_RW(noise_per_m) POLYLOC_RW(noise_per_m2) POLYLOC_RW(sigma_c) POLYLOC_RW(threshold)
                POLYLOC_RW(min_support) POLYLOC_RW(colour);
  }
  {
    using T = DepthSmoothing;
    pb::class_<T>(m, "DepthSmoothing", "smoothing: none | median | bilateral")
        .def(pb::init<>()) POLYLOC_RW(method) POLYLOC_RW(size) POLYLOC_RW(sigma_depth) POLYLOC_RW(sigma_space)
            POLYLOC_RW(max_change);
  }
  {
    using T = DepthFilterConfig;
    pb::class_<T>(m, "DepthFilterConfig", "Depth filter settings (the depth_filter: section; docs/depth.md has every key).")
        .def(pb::init<>()) POLYLOC_RW(validity) POLYLOC_RW(jump_edge) POLYLOC_RW(confidence) POLYLOC_RW(smoothing)
        .def_static("from_yaml", [](const std::string& text) { return parseDepthFilterConfig(ConfigMap::parse(text, "<depth_filter>")); },
                    pb::arg("text"), "From the YAML of a `depth_filter:` section (angles in degrees there).");
  }
}

#undef POLYLOC_RW

struct DepthFrameArrays {
  F32Array depth, amplitude;
  U8Array rgb;
  DepthFrameView view;
};

DepthFrameArrays frameArrays(const DepthCameraSpec& cam, const pb::handle& depth, const pb::handle& amplitude,
                             const pb::handle& rgb) {
  DepthFrameArrays f;
  const pb::ssize_t h = cam.height, w = cam.width;
  f.depth = floatArray(depth, "depth", {h, w});
  f.view = {cam.width, cam.height, f.depth.data(), nullptr, nullptr};
  if (!amplitude.is_none()) f.amplitude = floatArray(amplitude, "amplitude", {h, w}), f.view.amplitude = f.amplitude.data();
  if (!rgb.is_none()) f.rgb = byteArray(rgb, "rgb", {h, w, 3}), f.view.rgb = f.rgb.data();
  return f;
}

pb::dict counts(const DepthFilterResult& r) {
  pb::dict d;
  for (size_t k = 0; k < kDepthRejectKinds; ++k) d[depthRejectName(static_cast<DepthReject>(k))] = r.count[k];
  return d;
}

template <class T, class V>
pb::array_t<T> imageView(pb::object self, const std::vector<V> DepthFilterResult::*field) {
  const DepthFilterResult& r = self.cast<const DepthFilterResult&>();
  return view<T>(reinterpret_cast<const T*>((r.*field).data()), {r.height, r.width}, self);
}

}  // namespace depth_impl

void bindDepth(pb::module_& m) {
  using namespace depth_impl;
  bindDepthConfig(m);

  pb::class_<DepthFilterResult>(m, "DepthResult", "What DepthFilter.apply kept and why it dropped the rest.")
      .def_property_readonly("depth", [](pb::object s) { return imageView<float>(s, &DepthFilterResult::depth); },
                             "(H, W) float32 filtered depth, NaN where rejected")
      .def_property_readonly("valid", [](pb::object s) { return imageView<bool>(s, &DepthFilterResult::valid); },
                             "(H, W) bool, True where kept")
      .def_property_readonly("reason", [](pb::object s) { return imageView<uint8_t>(s, &DepthFilterResult::reason); },
                             "(H, W) uint8: index into DEPTH_REJECT_NAMES (0 kept)")
      .def_property_readonly("counts", &counts, "pixels per reason name")
      .def_property_readonly("kept", &DepthFilterResult::kept)
      .def_property_readonly("points", [](const DepthFilterResult& r) {
        pb::array_t<float> a({static_cast<pb::ssize_t>(r.x.size()), pb::ssize_t{3}});
        float* d = a.mutable_data();
        for (size_t i = 0; i < r.x.size(); ++i) d[3 * i] = r.x[i], d[3 * i + 1] = r.y[i], d[3 * i + 2] = r.z[i];
        return a;
      }, "(K, 3) float32: kept pixels as points in the base frame")
      .def_property_readonly("pixel", [](pb::object s) {
        const auto& r = s.cast<const DepthFilterResult&>();
        return view<uint32_t>(r.pixel.data(), {static_cast<pb::ssize_t>(r.pixel.size())}, s);
      }, "(K,) uint32 row-major pixel index of each point");

  pb::list names;
  for (size_t k = 0; k < kDepthRejectKinds; ++k) names.append(depthRejectName(static_cast<DepthReject>(k)));
  m.attr("DEPTH_REJECT_NAMES") = names;

  pb::class_<DepthFilter>(m, "DepthFilter", R"(ToF/PMD depth filtering: validity, jump edges (flying pixels), confidence, smoothing.

Depth images are (H, W) along the optical axis in metres, NaN/inf/<= 0 for no measurement
(amplitude and a registered (H, W, 3) uint8 RGB image are optional). Bad values are rejected
pixels, never errors; a wrong image shape is a ValueError.)")
      .def(pb::init([](const DepthCameraSpec& camera, const pb::handle& mount, const DepthFilterConfig& config) {
  using namespace depth_impl;
             return DepthFilter(camera, mount.is_none() ? Pose() : toPose(mount, "mount"), config);
           }),
           pb::arg("camera"), pb::arg("mount") = pb::none(), pb::arg("config") = DepthFilterConfig{},
           "camera: a DepthCameraSpec (sensor_preset('pmd_o3d100')); mount: base_T_sensor (points come out in base_link).")
      .def(pb::init([](const Sensor& sensor, const DepthFilterConfig& config) {
             const auto* cam = std::get_if<DepthCameraSpec>(&sensor.spec);
             if (!cam)
               raise(PyExc_ValueError,
                     fmt::format("DepthFilter: sensor '{}' is a {}, not a depth camera", sensor.name, sensor.typeName()));
             return DepthFilter(*cam, sensor.mount, config);
           }),
           pb::arg("sensor"), pb::arg("config") = DepthFilterConfig{}, "For a depth camera of a rig, at its mount.")
      .def_property_readonly("camera", &DepthFilter::camera)
      .def_property_readonly("config", &DepthFilter::config)
      .def("apply", [](const DepthFilter& f, const pb::handle& depth, const pb::handle& amplitude, const pb::handle& rgb) {
        const DepthFrameArrays in = frameArrays(f.camera(), depth, amplitude, rgb);
        DepthFilterResult out;
        {
          pb::gil_scoped_release nogil;
          f.apply(in.view, out);
        }
        return out;
      }, pb::arg("depth"), pb::arg("amplitude") = pb::none(), pb::arg("rgb") = pb::none(), "Filter one frame: a DepthResult.")
      .def("apply_batch", [](const DepthFilter& f, const pb::handle& depth, const pb::handle& amplitude) {
        const F32Array d = floatArray(depth, "depth", {-1, f.camera().height, f.camera().width});
        const bool amp = !amplitude.is_none();
        F32Array a;
        if (amp) a = floatArray(amplitude, "amplitude", {d.shape(0), f.camera().height, f.camera().width});
        const size_t n = static_cast<size_t>(d.shape(0)), px = f.camera().numBeams();
        std::vector<DepthFrameView> frames(n);
        for (size_t k = 0; k < n; ++k)
          frames[k] = {f.camera().width, f.camera().height, d.data() + k * px, amp ? a.data() + k * px : nullptr, nullptr};
        std::vector<DepthFilterResult> out(n);
        {
          pb::gil_scoped_release nogil;
          f.applyBatch(frames, out);
        }
        return out;
      }, pb::arg("depth"), pb::arg("amplitude") = pb::none(),
           "Filter a stack of frames (F, H, W) in parallel (TBB): a list of DepthResult.");
}

}  // namespace polyloc::py
