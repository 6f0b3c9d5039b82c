// Measurement models: how well each particle explains one frame of one rig sensor. Siblings:
// beam (beam_model.hpp), likelihood_field, depth, plane_fragments. The Localizer asks
// makeSensorModels for one model per rig sensor (config keys `model` for scanners and lidars,
// `depth_model` for depth cameras) and sums their log-likelihoods per sensor round.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace polyloc {

// One frame, as the Localizer hands it to a model.
struct SensorFrame {
  size_t sensor = 0;               // index into the rig
  int64_t stamp_ns = 0;
  std::span<const float> ranges;   // the sensor's beam order; NaN, inf, out of range: invalid
  Pose odom_T_base;                // odometry at the stamp: relates frames of different sensors
  uint64_t step = 0;               // update counter: the stream for counter-based random choices
  // The filter is not tracking (global localisation, lost, after a kidnapping): a sparse cloud
  // has no particle within a few centimetres of the truth, so models weigh with their wide,
  // tempered settings (e.g. beam.coarse_sigma_hit) and near misses keep their say.
  bool coarse = false;
};

// Tempering by beam count (MclConfig::effective_beams): the factor for a frame of `used` beams.
inline double countTempering(double effective_beams, size_t used) {
  return effective_beams > 0 && double(used) > effective_beams ? effective_beams / double(used) : 1.0;
}

class SensorModel {
 public:
  virtual ~SensorModel() = default;
  virtual const char* name() const = 0;
  // Adds each particle's (tempered) log-likelihood of the frame to loglik[p], p < particles.size().
  // Returns the number of measurements it used (beams, points, fragments); 0: nothing usable,
  // loglik untouched. Runs its parallel loops with TBB in the caller's arena.
  virtual size_t weigh(const ParticleSet& particles, const SensorFrame& frame, std::span<double> loglik) = 0;
  // log of the likelihood per measurement that the non-hit part of the model gives (random
  // returns, unexpected obstacles): a best particle below it explains nothing, the filter is lost.
  virtual double unexplainedLogLikelihood(size_t sensor) const = 0;
  // The factor the last weigh() multiplied the summed log-likelihood with (tempering; 1 = none).
  virtual double logScale() const = 0;
};

// Model names `model` may take, and `depth_model` (which adds "none": depth cameras ignored).
const std::vector<std::string>& sensorModelNames();

// Creates the model `name` for the rig. Throws std::invalid_argument for an unknown name or a
// rig the model cannot use (naming the sensor).
std::unique_ptr<SensorModel> makeSensorModel(const std::string& name, const RayCaster& caster,
                                             const Mesh& map, const Rig& rig, const MclConfig& config);

}  // namespace polyloc
