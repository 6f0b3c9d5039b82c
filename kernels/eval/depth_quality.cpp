// evaluateDepthFilter: runs the scenario, takes the camera's depth and amplitude images as the
// recording would hold them, and scores every filter variant against the frames' artefact tags.
// Frames are gathered per simulated second (on_progress) and filtered as one batch.
#include <polyloc/depth/filter.hpp>
#include <polyloc/eval/depth_quality.hpp>
#include <polyloc/sim/simulator.hpp>

#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>

namespace polyloc {

namespace {

struct Frame {
  std::vector<uint8_t> outlier_bits;  // kArtefactFlyingPixel | kArtefactReflection per pixel
  std::vector<uint8_t> finite;        // measured range finite
  std::vector<float> depth, amplitude;
  bool has_depth = false, has_amplitude = false;
};

std::vector<float> floats(const msg::Image& img) {
  std::vector<float> v(img.data.size() / sizeof(float));
  std::memcpy(v.data(), img.data.data(), v.size() * sizeof(float));
  return v;
}

// Keeps the camera's images, by stamp, until the frame is complete.
class ImageTap final : public RecordingWriter {
 public:
  ImageTap(std::string topic, std::map<int64_t, Frame>& frames) : base_(std::move(topic)), frames_(frames) {}
  void write(const std::string& topic, int64_t t, const msg::Message& m) override {
    const bool depth = topic == base_ + "/image", amp = topic == base_ + "/amplitude";
    if (!depth && !amp) return;
    Frame& f = frames_[t];
    (depth ? f.depth : f.amplitude) = floats(std::get<msg::Image>(m));
    (depth ? f.has_depth : f.has_amplitude) = true;
  }
  void close() override {}

 private:
  std::string base_;
  std::map<int64_t, Frame>& frames_;
};

void score(const Frame& f, const DepthFilterResult& r, DepthQualityCounts& c) {
  for (size_t i = 0; i < r.valid.size(); ++i) {
    const uint8_t bits = f.outlier_bits[i];
    const bool kept = r.valid[i];
    if (bits) {
      ++c.outliers, c.outliers_removed += !kept;
      if (bits & kArtefactFlyingPixel) ++c.flying, c.flying_removed += !kept;
      if (bits & kArtefactReflection) ++c.reflection, c.reflection_removed += !kept;
    } else if (f.finite[i]) {
      ++c.valid, c.valid_kept += kept;
    }
  }
}

}  // namespace

DepthQualityResult evaluateDepthFilter(const Scenario& scenario, const Mesh& map, const DepthFilterConfig& config,
                                       const DepthQualityOptions& options) {
  Scenario s = scenario;
  if (s.noise.sensors.size() != s.config.rig.size()) s.noise.sensors = defaultSensorNoise(s.config.rig);
  int index = -1;
  for (size_t k = 0; k < s.config.rig.size() && index < 0; ++k)
    if (std::holds_alternative<DepthCameraSpec>(s.config.rig.sensors[k].spec) &&
        (options.sensor.empty() || s.config.rig.sensors[k].name == options.sensor))
      index = int(k);
  if (index < 0)
    throw std::invalid_argument(options.sensor.empty() ? "the rig has no depth camera"
                                                       : "the rig has no depth camera '" + options.sensor + "'");
  const Sensor camera = s.config.rig.sensors[size_t(index)];
  if (options.camera_only) {
    Rig rig;
    rig.name = s.config.rig.name;
    rig.add(camera, s.config.rig.presets[size_t(index)]);
    const SensorNoise noise = s.noise.sensors[size_t(index)];
    s.config.rig = rig;
    s.noise.sensors = {noise};
    index = 0;
  }
  if (options.duration > 0) s.duration = options.duration;
  const auto& spec = std::get<DepthCameraSpec>(camera.spec);

  // The configuration as given, and each rejecting stage alone (after validity).
  DepthFilterConfig validity = config;
  validity.jump_edge.enabled = false, validity.confidence.enabled = false, validity.smoothing.method = "none";
  DepthFilterConfig jump = validity, conf = validity;
  jump.jump_edge.enabled = true;
  conf.confidence.enabled = true;
  const std::vector<DepthFilter> filters = {{spec, camera.mount, config}, {spec, camera.mount, validity},
                                            {spec, camera.mount, jump}, {spec, camera.mount, conf}};
  DepthQualityResult out;
  out.sensor = camera.name;
  out.per_filter = {{"validity", {}, 0}, {"jump_edge", {}, 0}, {"confidence", {}, 0}};

  std::map<int64_t, Frame> frames;
  ImageTap tap("/depth/" + camera.name, frames);
  const size_t n = spec.numBeams();
  std::vector<DepthFilterResult> results;
  auto flush = [&] {
    std::vector<const Frame*> ready;
    std::vector<DepthFrameView> views;
    for (const auto& [t, f] : frames)
      if (f.has_depth && f.has_amplitude && f.depth.size() == n && f.outlier_bits.size() == n) {
        ready.push_back(&f);
        views.push_back({spec.width, spec.height, f.depth.data(), f.amplitude.data(), nullptr});
      }
    results.resize(views.size());
    for (size_t k = 0; k < filters.size(); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      filters[k].applyBatch(views, results);
      if (k == 0) out.filter_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      for (size_t j = 0; j < views.size(); ++j) {
        score(*ready[j], results[j], k == 0 ? out.combined : out.per_filter[k - 1].counts);
        if (k == 0)
          for (size_t r = 0; r < kDepthRejectKinds; ++r) out.rejected[r] += results[j].count[r];
      }
    }
    out.frames += views.size();
    out.pixels += views.size() * n;
    for (auto it = frames.begin(); it != frames.end();)
      it = it->second.has_depth && it->second.has_amplitude ? frames.erase(it) : std::next(it);
  };

  Simulator sim(std::move(s), map);
  SimHooks hooks;
  hooks.on_frame = [&](const SimFrame& f) {
    if (f.sensor != size_t(index)) return;
    Frame& fr = frames[f.stamp_ns];  // the stamp of its messages
    fr.outlier_bits.resize(f.artefacts.size());
    fr.finite.resize(f.measured.size());
    for (size_t i = 0; i < f.artefacts.size(); ++i) {
      fr.outlier_bits[i] = f.artefacts[i] & (kArtefactFlyingPixel | kArtefactReflection);
      fr.finite[i] = std::isfinite(f.measured[i]);
    }
  };
  hooks.on_progress = [&](double) { flush(); };
  sim.run(tap, hooks);
  flush();
  out.per_filter[1].rejected = out.rejected[size_t(DepthReject::kJumpEdge)];
  out.per_filter[2].rejected = out.rejected[size_t(DepthReject::kConfidence)];
  out.per_filter[0].rejected = out.rejected[size_t(DepthReject::kRange)] + out.rejected[size_t(DepthReject::kAmplitude)];
  return out;
}

}  // namespace polyloc
