#include <polyloc/geometry/random.hpp>
#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/raycast/scan_score.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace polyloc {

BeamSensorModel::BeamSensorModel(const RayCaster& caster, const Rig& rig, const MclConfig& config)
    : caster_(caster), rig_(rig), config_(config) {
  for (const auto& s : rig.sensors) sensor_beams_.push_back(s.beams());
}

double BeamSensorModel::unexplainedLogLikelihood(size_t sensor) const {
  const auto& m = config_.beam;
  return std::log(m.z_short * m.lambda_short + m.z_rand / sensor_beams_.at(sensor).range_max);
}

std::vector<size_t> BeamSensorModel::selectBeams(const BeamSet& beams, std::span<const float> ranges,
                                                 size_t max_beams, const std::string& strategy,
                                                 uint64_t seed, uint64_t stream) {
  std::vector<size_t> valid;
  for (size_t b = 0; b < ranges.size() && b < beams.size(); ++b) {
    const float r = ranges[b];
    // A max-range return says "nothing within range_max" but a window cannot check that cheaply.
    if (std::isfinite(r) && r >= beams.range_min && r < beams.range_max) valid.push_back(b);
  }
  if (max_beams == 0 || valid.size() <= max_beams) return valid;
  if (strategy == "random") {
    // Partial Fisher-Yates: max_beams distinct beams, then back in beam order (cache-friendly).
    const CounterRng rng(seed);
    for (size_t i = 0; i < max_beams; ++i) {
      const size_t j = i + std::min(valid.size() - i - 1, size_t(rng.uniform(stream, i) * double(valid.size() - i)));
      std::swap(valid[i], valid[j]);
    }
    valid.resize(max_beams);
    std::sort(valid.begin(), valid.end());
    return valid;
  }
  // Evenly spread over the valid beams: the whole field of view keeps its say.
  std::vector<size_t> out(max_beams);
  for (size_t i = 0; i < max_beams; ++i) out[i] = valid[(i * valid.size()) / max_beams];
  return out;
}

double BeamSensorModel::logLikelihood(double z, double e, double range_max, const BeamModel& m) {
  const double p_rand = m.z_rand / range_max;
  double p_short = 0;
  double p_hit = 0;
  if (std::isfinite(e)) {
    const double d = (z - e) / m.sigma_hit;
    p_hit = m.z_hit * std::exp(-0.5 * d * d) / (m.sigma_hit * 2.5066282746310002);
    if (z < e) p_short = m.z_short * m.lambda_short * std::exp(-m.lambda_short * z) / (1.0 - std::exp(-m.lambda_short * e));
  } else {
    // Expected outside the window: if beyond, z was a short (unexpected obstacle); if before,
    // only a random return. Which one is unknown; the short density is the generous choice.
    p_short = m.z_short * m.lambda_short * std::exp(-m.lambda_short * z);
  }
  return std::log(p_hit + p_short + p_rand);
}

size_t BeamSensorModel::weigh(const ParticleSet& ps, const SensorFrame& frame, std::span<double> loglik) {
  const MclConfig& cfg = config_;
  const std::vector<size_t> sel = selectBeams(sensor_beams_[frame.sensor], frame.ranges, cfg.beams_per_scan,
                                              cfg.subsample, cfg.seed, (uint64_t(frame.sensor) << 48) + frame.step);
  return weighSelected(ps, frame, sel, 0.0, loglik);
}

size_t BeamSensorModel::weighSelected(const ParticleSet& ps, const SensorFrame& frame, const std::vector<size_t>& sel,
                                      double sigma_per_m, std::span<double> loglik) {
  const MclConfig& cfg = config_;
  const Sensor& sensor = rig_.sensors.at(frame.sensor);
  const BeamSet& all = sensor_beams_[frame.sensor];
  const std::span<const float> ranges = frame.ranges;
  const size_t B = sel.size(), P = ps.size();
  if (B == 0 || P == 0) return 0;
  BeamModel m = cfg.beam;
  if (frame.coarse) m.sigma_hit = m.coarse_sigma_hit, m.log_scale = m.coarse_log_scale;
  else m.log_scale *= countTempering(cfg.effective_beams, B);
  last_log_scale_ = m.log_scale;
  // Per beam: sigma grows with range where the sensor's noise does (ToF: about 1% of range).
  hit_scale_.resize(B), half_inv_var_.resize(B);
  for (size_t i = 0; i < B; ++i) {
    const double sr = sigma_per_m * ranges[sel[i]];
    const double sigma = std::sqrt(m.sigma_hit * m.sigma_hit + sr * sr);
    hit_scale_[i] = float(m.z_hit / (sigma * 2.5066282746310002));
    half_inv_var_[i] = float(0.5 / (sigma * sigma));
  }
  beams_.dx.resize(B), beams_.dy.resize(B), beams_.dz.resize(B);
  beams_.range_min = all.range_min, beams_.range_max = all.range_max;
  measured_.resize(B), tmin_.resize(B), tmax_.resize(B);
  for (size_t i = 0; i < B; ++i) {
    const size_t b = sel[i];
    beams_.dx[i] = all.dx[b], beams_.dy[i] = all.dy[b], beams_.dz[i] = all.dz[b];
    measured_[i] = ranges[b];
    const double w = std::max(m.window_sigmas * std::sqrt(0.5 / half_inv_var_[i]), m.window_min);
    tmin_[i] = std::max<float>(all.range_min, ranges[b] - w);
    tmax_[i] = std::min<float>(all.range_max, ranges[b] + w);
  }
  poses_.resize(P);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, P, 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) poses_[p] = sensor.worldPose(ps.pose(p));
  });
  // Per beam, the parts of the mixture that do not depend on the particle; the short term's
  // normaliser 1 / (1 - exp(-lambda e)) is taken at the measured range (the expected range e
  // lies within the window around it), so a beam costs one expf and one logf per particle.
  const double rmax = all.range_max;
  const float p_rand = float(m.z_rand / rmax);
  short_.resize(B), miss_.resize(B);
  for (size_t i = 0; i < B; ++i) {
    const double z = measured_[i];
    const double dens = m.z_short * m.lambda_short * std::exp(-m.lambda_short * z);
    short_[i] = float(dens / std::max(1e-6, 1.0 - std::exp(-m.lambda_short * z)));
    miss_[i] = float(logLikelihood(z, std::numeric_limits<double>::infinity(), rmax, m));
  }
  // With one sigma for all beams (no range-dependent noise) the hit density is tabulated over
  // |d| in [0, window]: a lookup replaces expf, and for d >= 0 (no short term) also logf.
  const bool table = sigma_per_m == 0 && B > 0;
  double w_max = 0;
  for (size_t i = 0; i < B; ++i) w_max = std::max(w_max, double(std::max(tmax_[i] - measured_[i], measured_[i] - tmin_[i])));
  constexpr size_t kTable = 2048;
  const float step = float(w_max / double(kTable - 2)), inv_step = step > 0 ? 1.f / step : 0.f;
  if (table) {
    hit_table_.resize(kTable), log_table_.resize(kTable);
    for (size_t k = 0; k < kTable; ++k) {
      const float d = float(k) * step;
      hit_table_[k] = hit_scale_[0] * std::exp(-half_inv_var_[0] * d * d);
      log_table_[k] = std::log(hit_table_[k] + p_rand);
    }
  }
  ScanScoring scoring{measured_.data(), miss_.data(), short_.data(), hit_scale_.data(), half_inv_var_.data(), p_rand};
  if (table) scoring.hit_table = hit_table_.data(), scoring.log_table = log_table_.data(), scoring.table_size = kTable;
  scoring.inv_step = inv_step;
  const ScanWindow window{tmin_.data(), tmax_.data()};
  if (const auto* scorer = dynamic_cast<const ScanScorer*>(&caster_)) {
    // The caster sums where it casts (a GPU): only one number a particle comes back.
    sums_.resize(P);
    scorer->scoreScans(poses_, beams_, window, scoring, sums_.data());
    for (size_t p = 0; p < P; ++p) loglik[p] += m.log_scale * sums_[p];
    return B;
  }
  // The particles in blocks of at most kMaxHits rays: a global round of 10^7 particles x 1,000
  // beams would otherwise keep 40 GB of ranges. Per particle, a sequential sum over its beams:
  // the same for any split over threads or blocks.
  const size_t block = std::max<size_t>(1, kMaxHits / std::max<size_t>(B, 1));
  hits_.resize(std::min(P, block) * B);
  for (size_t first = 0; first < P; first += block) {
    const size_t n = std::min(block, P - first);
    HitBuffers out;
    out.range = hits_.data();
    caster_.castScans(std::span<const Pose>(poses_).subspan(first, n), beams_, out, window);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t p = r.begin(); p < r.end(); ++p)
        loglik[first + p] += m.log_scale * scoreHits(hits_.data() + p * B, B, scoring);
    });
  }
  return B;
}

}  // namespace polyloc
