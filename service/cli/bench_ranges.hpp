// Ranges of a backend against reference ranges (Embree's exact intersection) on the same rays, as
// the `polyloc bench` commands report them: error statistics where both hit, how often they
// disagree about hitting at all, and how often they agree within 1 mm (both misses agree).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace polyloc::cli {

struct RangeStats {
  double mean = 0, median = 0, p99 = 0;  // m, |r - ref| where both hit
  double hit_disagreement = 0;          // share of rays that one hits and the other misses
  double agree_1mm = 1;                 // share within 1 mm, both misses counted as agreeing
};

inline RangeStats rangeStats(const std::vector<float>& r, const std::vector<float>& ref) {
  RangeStats s;
  std::vector<double> e;
  size_t disagree = 0, same = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    const bool a = std::isfinite(r[i]), b = std::isfinite(ref[i]);
    disagree += a != b;
    same += (!a && !b) || std::abs(r[i] - ref[i]) <= 1e-3f;
    if (a && b) e.push_back(std::abs(double(r[i]) - double(ref[i])));
  }
  std::sort(e.begin(), e.end());
  if (!e.empty()) {
    for (double v : e) s.mean += v;
    s.mean /= double(e.size());
    s.median = e[e.size() / 2];  // the mean is a tail's: near misses
    s.p99 = e[std::min(e.size() - 1, size_t(0.99 * double(e.size())))];
  }
  if (!r.empty()) {
    s.hit_disagreement = double(disagree) / double(r.size());
    s.agree_1mm = double(same) / double(r.size());
  }
  return s;
}

}  // namespace polyloc::cli
