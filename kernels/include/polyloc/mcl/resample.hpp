// Resampling: weights normalised in log space, effective sample size, systematic (low-variance)
// resampling, and the KLD-sampling bound on the particle count (Fox 2003).
#pragma once

#include <polyloc/geometry/random.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/particles.hpp>

#include <cstdint>
#include <vector>

namespace polyloc {

// Shifts and normalises logw so that sum(exp(logw)) = 1. Returns false when every weight is
// zero (-inf or NaN); the weights are then made uniform.
bool normalizeLogWeights(std::vector<double>& logw);
// 1 / sum(w^2) of normalised weights.
double effectiveSampleSize(const std::vector<double>& logw);
// `n` indices drawn with one uniform offset (CounterRng(stream, 0)); the output is sorted.
std::vector<size_t> systematicResample(const std::vector<double>& logw, size_t n,
                                       const CounterRng& rng, uint64_t stream);
// Particles needed so that, with probability 1 - delta (z quantile), the KL distance between the
// sample and the true posterior stays below epsilon, for k occupied bins; clamped to bounds.
size_t kldParticleCount(size_t occupied_bins, const MclConfig& config);
// Occupied (x, y, yaw) bins of the particles at `indices` of set s.
size_t occupiedBins(const ParticleSet& s, const std::vector<size_t>& indices, const MclConfig& config);

}  // namespace polyloc
