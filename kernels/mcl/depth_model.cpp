#include <polyloc/mcl/depth_model.hpp>

#include <cmath>
#include <variant>

namespace polyloc {

DepthSensorModel::DepthSensorModel(const RayCaster& caster, const Rig& rig, const MclConfig& config)
    : BeamSensorModel(caster, rig, config) {}

std::vector<size_t> DepthSensorModel::selectPixels(const DepthCameraSpec& cam, std::span<const float> ranges,
                                                   const DepthModel& cfg) {
  const size_t W = size_t(cam.width), H = size_t(cam.height);
  std::vector<size_t> out;
  if (ranges.size() != W * H || W == 0 || H == 0) return out;
  auto valid = [&](size_t i) {
    const float r = ranges[i];
    return std::isfinite(r) && r >= cam.range_min && r < cam.range_max;
  };
  size_t n_valid = 0;
  for (size_t i = 0; i < ranges.size(); ++i) n_valid += valid(i);
  if (n_valid == 0) return out;
  const size_t stride = std::max<size_t>(1, size_t(std::sqrt(double(n_valid) / double(std::max<size_t>(cfg.pixels, 1)))));
  // A neighbour one stride away in each direction: a jump there marks an edge (flying pixels).
  auto smooth = [&](size_t u, size_t v) {
    const float r = ranges[v * W + u];
    const size_t nb[4][2] = {{u + stride, v}, {u - stride, v}, {u, v + stride}, {u, v - stride}};
    for (const auto& q : nb) {
      if (q[0] >= W || q[1] >= H) continue;  // off the image (unsigned wrap included)
      const size_t j = q[1] * W + q[0];
      if (valid(j) && std::abs(ranges[j] - r) > cfg.jump_ratio * r) return false;
    }
    return true;
  };
  for (size_t v = stride / 2; v < H; v += stride)
    for (size_t u = stride / 2; u < W; u += stride)
      if (valid(v * W + u) && smooth(u, v)) out.push_back(v * W + u);
  return out;
}

size_t DepthSensorModel::weigh(const ParticleSet& ps, const SensorFrame& frame, std::span<double> loglik) {
  const auto* cam = std::get_if<DepthCameraSpec>(&rig_.sensors.at(frame.sensor).spec);
  if (!cam) return BeamSensorModel::weigh(ps, frame, loglik);
  return weighSelected(ps, frame, selectPixels(*cam, frame.ranges, config_.depth), config_.depth.sigma_per_m, loglik);
}

}  // namespace polyloc
