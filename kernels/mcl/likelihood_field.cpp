#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/likelihood_field.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace polyloc {
namespace {

// Table of log p over [0, max_distance]: linear interpolation between 4096 samples is off by
// < 1e-5 for sigma_hit >= 1 cm (the curvature of log p is 1 / sigma_hit^2), and replaces an exp
// and a log per beam and particle.
constexpr size_t kTableSize = 4096;

DistanceFieldConfig fieldConfig(const LikelihoodField& m) {
  DistanceFieldConfig c;
  c.resolution = m.resolution;
  c.max_distance = m.max_distance;
  c.padding = m.max_distance;
  return c;
}

}  // namespace

LikelihoodFieldModel::LikelihoodFieldModel(const Mesh& map, const Rig& rig, const MclConfig& config)
    : rig_(rig), config_(config), field_(map, fieldConfig(config.likelihood_field)) {
  const LikelihoodField& m = config.likelihood_field;
  const double step = m.max_distance / double(kTableSize - 1);
  table_inv_step_ = 1.0 / step;
  for (const auto& s : rig.sensors) {
    sensor_beams_.push_back(s.beams());
    std::vector<double>& t = tables_.emplace_back(kTableSize);
    for (size_t i = 0; i < kTableSize; ++i) t[i] = logLikelihood(double(i) * step, sensor_beams_.back().range_max, m);
  }
}

double LikelihoodFieldModel::logLikelihood(double d, double range_max, const LikelihoodField& m) {
  const double u = d / m.sigma_hit;
  const double p_hit = m.z_hit * std::exp(-0.5 * u * u) / (m.sigma_hit * 2.5066282746310002);
  return std::log(p_hit + m.z_rand / range_max);
}

double LikelihoodFieldModel::unexplainedLogLikelihood(size_t sensor) const {
  return logLikelihood(3.0 * config_.likelihood_field.sigma_hit, sensor_beams_.at(sensor).range_max,
                       config_.likelihood_field);
}

double LikelihoodFieldModel::tableLookup(const std::vector<double>& table, float d) const {
  const double t = double(d) * table_inv_step_;
  const size_t i = std::min(size_t(t), kTableSize - 2);
  const double f = std::min(t - double(i), 1.0);
  return table[i] + f * (table[i + 1] - table[i]);
}

size_t LikelihoodFieldModel::weigh(const ParticleSet& ps, const SensorFrame& frame, std::span<double> loglik) {
  const MclConfig& cfg = config_;
  const Sensor& sensor = rig_.sensors.at(frame.sensor);
  const BeamSet& all = sensor_beams_[frame.sensor];
  const std::span<const float> ranges = frame.ranges;
  // The same beams the beam model would take for this frame (same stream).
  const std::vector<size_t> sel = BeamSensorModel::selectBeams(all, ranges, cfg.beams_per_scan, cfg.subsample,
                                                               cfg.seed, (uint64_t(frame.sensor) << 48) + frame.step);
  const size_t B = sel.size(), P = ps.size();
  if (B == 0 || P == 0) return 0;
  ex_.resize(B), ey_.resize(B), ez_.resize(B);
  for (size_t i = 0; i < B; ++i) {
    const size_t b = sel[i];
    ex_[i] = all.dx[b] * ranges[b], ey_[i] = all.dy[b] * ranges[b], ez_[i] = all.dz[b] * ranges[b];
  }
  const std::vector<double>& table = tables_[frame.sensor];
  const double log_scale = cfg.likelihood_field.log_scale * (frame.coarse ? 1.0 : countTempering(cfg.effective_beams, B));
  last_log_scale_ = log_scale;
  // Per particle, a sequential sum over its beams: the same for any split over threads.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, P, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) {
      const Pose sp = sensor.worldPose(ps.pose(p));
      const Eigen::Matrix3f R = sp.rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f t = sp.translation().cast<float>();
      double s = 0;
      for (size_t i = 0; i < B; ++i) {
        const Eigen::Vector3f e = R * Eigen::Vector3f(ex_[i], ey_[i], ez_[i]) + t;
        s += tableLookup(table, field_.distance(e));
      }
      loglik[p] += log_scale * s;
    }
  });
  return B;
}

}  // namespace polyloc
