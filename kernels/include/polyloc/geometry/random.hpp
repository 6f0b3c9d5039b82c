// Counter-based random numbers: a draw is a pure function of (seed, stream, index, k), so the
// same particle gets the same noise however the work is split over threads. Stateless, cheap
// (two rounds of the SplitMix64 finalizer), good enough for Monte-Carlo sampling.
#pragma once

#include <cmath>
#include <cstdint>

namespace polyloc {

class CounterRng {
 public:
  explicit CounterRng(uint64_t seed = 0) : seed_(seed) {}

  // 64 random bits for draw k of item `index` at step `stream`.
  uint64_t bits(uint64_t stream, uint64_t index, uint64_t k = 0) const {
    uint64_t h = mix(seed_ ^ mix(stream + 0x9E3779B97F4A7C15ULL));
    h = mix(h ^ (index * 0xD1B54A32D192ED03ULL));
    return mix(h ^ (k * 0xAEF17502108EF2D9ULL + 0x632BE59BD9B4E019ULL));
  }
  // Uniform in [0, 1).
  double uniform(uint64_t stream, uint64_t index, uint64_t k = 0) const {
    return static_cast<double>(bits(stream, index, k) >> 11) * 0x1.0p-53;
  }
  double uniform(double lo, double hi, uint64_t stream, uint64_t index, uint64_t k = 0) const {
    return lo + (hi - lo) * uniform(stream, index, k);
  }
  // Standard normal (Box-Muller on draws 2k and 2k+1).
  double normal(uint64_t stream, uint64_t index, uint64_t k = 0) const {
    const double u1 = 1.0 - uniform(stream, index, 2 * k);  // (0, 1]: log stays finite
    const double u2 = uniform(stream, index, 2 * k + 1);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  uint64_t seed_;
};

}  // namespace polyloc
