// The text of a terminal progress bar, "[=====     ]", for the long jobs' progress lines.
#pragma once

#include <algorithm>
#include <string>

namespace polyloc::cli {

inline std::string barText(double fraction, int width = 40) {
  const int done = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * width);
  return "[" + std::string(done, '=') + std::string(width - done, ' ') + "]";
}

}  // namespace polyloc::cli
