// Depth-camera model: the beam mixture over a sub-sampled pixel grid of a ToF/depth frame.
// Pixels are taken on a regular grid (every `stride` rows and columns, chosen so that about
// depth.pixels valid pixels remain), so the whole field of view keeps its say, and a pixel whose
// range jumps against a grid neighbour by more than depth.jump_ratio of its range is skipped: on
// a ToF camera those are flying pixels (mixtures of foreground and background) that no map
// explains. The hit noise grows with range (ToF: about 1% of the range). Frames of sensors that
// are not depth cameras are weighed as by the beam model.
#pragma once

#include <polyloc/mcl/beam_model.hpp>

namespace polyloc {

class DepthSensorModel : public BeamSensorModel {
 public:
  DepthSensorModel(const RayCaster& caster, const Rig& rig, const MclConfig& config);
  const char* name() const override { return "depth"; }
  size_t weigh(const ParticleSet& particles, const SensorFrame& frame, std::span<double> loglik) override;

  // The pixels weigh() uses (indices into the sensor's beams, row-major).
  static std::vector<size_t> selectPixels(const DepthCameraSpec& camera, std::span<const float> ranges,
                                          const DepthModel& config);
};

}  // namespace polyloc
