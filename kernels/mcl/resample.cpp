#include <polyloc/mcl/resample.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

namespace polyloc {

bool normalizeLogWeights(std::vector<double>& logw) {
  double mx = -std::numeric_limits<double>::infinity();
  for (double l : logw)
    if (l > mx) mx = l;  // NaN compares false: ignored
  if (logw.empty() || !std::isfinite(mx)) {
    std::fill(logw.begin(), logw.end(), -std::log(double(std::max<size_t>(logw.size(), 1))));
    return false;
  }
  double sum = 0;
  for (double& l : logw) {
    if (std::isnan(l)) l = -std::numeric_limits<double>::infinity();
    sum += std::exp(l - mx);
  }
  const double shift = mx + std::log(sum);
  for (double& l : logw) l -= shift;
  return true;
}

double effectiveSampleSize(const std::vector<double>& logw) {
  double s2 = 0;
  for (double l : logw) s2 += std::exp(2 * l);
  return s2 > 0 ? 1.0 / s2 : 0.0;
}

std::vector<size_t> systematicResample(const std::vector<double>& logw, size_t n,
                                       const CounterRng& rng, uint64_t stream) {
  std::vector<size_t> out;
  if (logw.empty() || n == 0) return out;
  out.reserve(n);
  const double step = 1.0 / double(n);
  double u = rng.uniform(stream, 0) * step;
  double c = std::exp(logw[0]);
  size_t i = 0;
  for (size_t j = 0; j < n; ++j, u += step) {
    while (u > c && i + 1 < logw.size()) c += std::exp(logw[++i]);
    out.push_back(i);
  }
  return out;
}

size_t kldParticleCount(size_t k, const MclConfig& cfg) {
  double n = double(cfg.min_particles);
  if (k > 1) {
    const double a = 2.0 / (9.0 * double(k - 1));
    const double b = 1.0 - a + std::sqrt(a) * cfg.kld_z;
    n = double(k - 1) / (2.0 * cfg.kld_epsilon) * b * b * b;
  }
  return std::clamp<size_t>(size_t(std::ceil(n)), cfg.min_particles, std::max(cfg.min_particles, cfg.max_particles));
}

size_t occupiedBins(const ParticleSet& s, const std::vector<size_t>& idx, const MclConfig& cfg) {
  std::unordered_set<uint64_t> bins;
  bins.reserve(idx.size());
  for (size_t i : idx) {
    const Pose p = s.pose(i);
    const auto bx = int64_t(std::floor(p.x() / cfg.kld_bin_xy)) & 0x1FFFFF;
    const auto by = int64_t(std::floor(p.y() / cfg.kld_bin_xy)) & 0x1FFFFF;
    const auto bt = int64_t(std::floor((p.yaw() + M_PI) / cfg.kld_bin_yaw)) & 0x3FFFFF;
    bins.insert(uint64_t(bx) << 43 | uint64_t(by) << 22 | uint64_t(bt));
  }
  return bins.size();
}

}  // namespace polyloc
