// Beam measurement model (Thrun's hit/short/max/rand mixture, in log space) for one scan of one
// sensor against every particle. All particles x selected beams are one castScans call, each
// beam windowed to [measured - w, measured + w] so Embree stops early: within the window the
// expected range is known exactly; a ray that finds nothing there means the expected range lies
// outside, where only the short and random parts of the mixture can explain the measurement.
// Invalid beams (NaN, inf, outside [range_min, range_max), max-range returns) carry no
// information and are skipped.
#pragma once

#include <polyloc/mcl/sensor_model.hpp>

#include <span>
#include <vector>

namespace polyloc {

class BeamSensorModel : public SensorModel {
 public:
  BeamSensorModel(const RayCaster& caster, const Rig& rig, const MclConfig& config);
  const char* name() const override { return "beam"; }
  size_t weigh(const ParticleSet& particles, const SensorFrame& frame, std::span<double> loglik) override;
  double unexplainedLogLikelihood(size_t sensor) const override;
  double logScale() const override { return last_log_scale_; }

  // Valid beams of a scan (indices into the sensor's beams), at most max_beams of them (0: all):
  // "uniform" spreads them evenly over the valid ones, "random" draws them without repetition
  // from counter-based random numbers of `stream` (the same for any thread count).
  static std::vector<size_t> selectBeams(const BeamSet& beams, std::span<const float> ranges,
                                         size_t max_beams, const std::string& strategy = "uniform",
                                         uint64_t seed = 0, uint64_t stream = 0);

  // Weighs the beams `sel` (indices into the sensor's beams) of the frame; sigma_hit grows by
  // sigma_per_m per metre of measured range (added in quadrature). For siblings that choose
  // beams their own way (depth_model.hpp).
  size_t weighSelected(const ParticleSet& particles, const SensorFrame& frame, const std::vector<size_t>& sel,
                       double sigma_per_m, std::span<double> loglik);

  // log p(measured | expected), expected = +inf when outside the window.
  static double logLikelihood(double measured, double expected, double range_max, const BeamModel& m);

  // Rays cast at once: the particles go in blocks of this many rays (64 MiB of ranges).
  static constexpr size_t kMaxHits = size_t(1) << 24;
  size_t hitsCapacity() const { return hits_.capacity(); }  // ranges kept between calls

 protected:
  const RayCaster& caster_;
  const Rig& rig_;
  const MclConfig& config_;
  std::vector<BeamSet> sensor_beams_;
  double last_log_scale_ = 1.0;

 private:
  // Reused between calls: no allocation once sizes settle.
  BeamSet beams_;
  std::vector<float> measured_, tmin_, tmax_, hits_, short_, miss_, hit_scale_, half_inv_var_, hit_table_, log_table_;
  std::vector<double> sums_;
  std::vector<Pose> poses_;
};

}  // namespace polyloc
