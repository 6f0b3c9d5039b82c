// Small statistics over error samples, as the metrics report them.
#pragma once

#include <span>
#include <vector>

namespace polyloc {

// p-th percentile (0..100) with linear interpolation between order statistics (numpy's default:
// rank p/100 * (n - 1)). NaN for no samples. Takes a copy: it partially sorts.
double percentile(std::vector<double> v, double p);
// Root mean square; NaN for no samples.
double rms(std::span<const double> v);
// Largest absolute value; NaN for no samples.
double maxAbs(std::span<const double> v);

}  // namespace polyloc
