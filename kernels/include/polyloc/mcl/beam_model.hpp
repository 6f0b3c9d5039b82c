// Beam measurement model (Thrun's hit/short/max/rand mixture, in log space) for one scan of one
// sensor against every particle. All particles x selected beams are one castScans call, each
// beam windowed to [measured - w, measured + w] so Embree stops early: within the window the
// expected range is known exactly; a ray that finds nothing there means the expected range lies
// outside, where only the short and random parts of the mixture can explain the measurement.
// Invalid beams (NaN, inf, outside [range_min, range_max), max-range returns) carry no
// information and are skipped.
#pragma once

#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/sensor.hpp>

#include <span>
#include <vector>

namespace polyloc {

class BeamWeigher {
 public:
  // Adds each particle's log-likelihood of `ranges` to loglik[p] (size particles.size()).
  // Returns the number of beams used (0: nothing usable, loglik untouched).
  size_t weigh(const RayCaster& caster, const ParticleSet& particles, const Sensor& sensor,
               const BeamSet& all_beams, std::span<const float> ranges, const MclConfig& config,
               std::span<double> loglik);

  // The same beam selection weigh() makes (indices into the sensor's beams).
  static std::vector<size_t> selectBeams(const BeamSet& beams, std::span<const float> ranges,
                                         size_t max_beams);

  // log p(measured | expected), expected = +inf when outside the window.
  static double logLikelihood(double measured, double expected, double range_max, const BeamModel& m);

 private:
  // Reused between calls: no allocation once sizes settle.
  BeamSet beams_;
  std::vector<float> measured_, tmin_, tmax_, hits_;
  std::vector<Pose> poses_;
};

}  // namespace polyloc
