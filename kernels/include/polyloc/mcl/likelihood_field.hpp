// Likelihood-field (endpoint) measurement model (Thrun, Probabilistic Robotics 6.4) in 3D: each
// selected beam's endpoint, put in the map by the particle's pose, is scored by its distance d to
// the nearest map surface, p = z_hit * N(d; 0, sigma_hit) + z_rand / range_max, in log space.
// No rays are cast: d comes from a DistanceField3D built once from the mesh (a few seconds and
// ~60 MB for a 25 m x 15 m building at 5 cm), so an update costs one trilinear lookup per beam and
// particle. Unlike the beam model it does not see through walls (an endpoint behind a wall scores
// as well as one on it) and ignores free space along the beam: cheaper and smoother, less
// discriminative. Beams are chosen as the beam model chooses them; invalid and max-range returns
// carry no endpoint and are skipped.
#pragma once

#include <polyloc/map/distance_field.hpp>
#include <polyloc/mcl/sensor_model.hpp>

#include <span>
#include <vector>

namespace polyloc {

class LikelihoodFieldModel : public SensorModel {
 public:
  // Builds the distance field of `map` (config.likelihood_field: resolution, max_distance; the
  // grid is padded by max_distance so that endpoints outside it are exactly "far").
  LikelihoodFieldModel(const Mesh& map, const Rig& rig, const MclConfig& config);
  const char* name() const override { return "likelihood_field"; }
  size_t weigh(const ParticleSet& particles, const SensorFrame& frame, std::span<double> loglik) override;
  // log(z_hit * N(3 sigma_hit) + z_rand / range_max): an endpoint three sigma off every surface
  // is no longer explained by the map. Not just log(z_rand / range_max): every endpoint scores
  // at least that, so a best particle could never fall below it and "lost" would never show.
  double unexplainedLogLikelihood(size_t sensor) const override;
  double logScale() const override { return last_log_scale_; }

  // log p of an endpoint at distance d (m) from the map, exactly (weigh uses a table of it).
  static double logLikelihood(double d, double range_max, const LikelihoodField& m);
  const DistanceField3D& field() const { return field_; }

 private:
  double tableLookup(const std::vector<double>& table, float d) const;

  const Rig& rig_;
  const MclConfig& config_;
  DistanceField3D field_;
  std::vector<BeamSet> sensor_beams_;
  // Per sensor: logLikelihood at d = i * table_step_, i < kTableSize (range_max differs per sensor).
  std::vector<std::vector<double>> tables_;
  double table_inv_step_ = 0;
  double last_log_scale_ = 1.0;
  // Reused between calls: no allocation once sizes settle.
  std::vector<float> ex_, ey_, ez_;  // endpoints of the selected beams, sensor frame
};

}  // namespace polyloc
