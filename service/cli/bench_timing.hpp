// Timing helpers of the `polyloc bench` commands.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>

namespace polyloc::cli {

inline double seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Best of `repeat` runs of n items: the machine is shared, the minimum is the least disturbed.
inline double bestRate(int repeat, double n, const std::function<void()>& f) {
  double best = 0;
  for (int i = 0; i < repeat; ++i) best = std::max(best, n / seconds(f));
  return best;
}

}  // namespace polyloc::cli
