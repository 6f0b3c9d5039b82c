// A number typed on the command line: the whole text must be one finite number, else an error
// that names the argument and quotes what was typed.
#pragma once

#include <polyloc/geometry/domain.hpp>
#include <polyloc/geometry/pose.hpp>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <stdexcept>
#include <algorithm>
#include <string>
#include <vector>

namespace polyloc::cli {

inline double parseNumber(const std::string& text, const char* what) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v))
    throw std::runtime_error(fmt::format("{}: '{}' is not a number", what, text));
  return v;
}

// "a,b,,c" -> {"a", "b", "c"}: a comma-separated list as typed, empty items dropped.
inline std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  for (size_t i = 0; i <= text.size();) {
    const size_t j = std::min(text.find(',', i), text.size());
    if (j > i) out.push_back(text.substr(i, j - i));
    i = j + 1;
  }
  return out;
}

// "1,2.5,-3": each item a number (parseNumber), the error naming `what`.
inline std::vector<double> parseNumbers(const std::string& text, const char* what) {
  std::vector<double> v;
  for (const std::string& item : splitList(text)) v.push_back(parseNumber(item, what));
  return v;
}

// A start pose as every command takes it (--init): "x,y,yaw" or "x,y,z,yaw", metres and degrees.
inline Pose parseStartPose(const std::string& text, const char* what) {
  const std::vector<double> v = parseNumbers(text, what);
  if (v.size() != 3 && v.size() != 4) throw std::runtime_error(fmt::format("{}: expected x,y,yaw or x,y,z,yaw (m, deg), got '{}'", what, text));
  if (auto why = domain::checkValue("yaw", deg2rad(v.back()), domain::kMaxAngle)) throw std::runtime_error(fmt::format("{}: {}", what, *why));
  return Pose::fromXYZRPY(v[0], v[1], v.size() == 4 ? v[2] : 0.0, 0, 0, deg2rad(v.back()));
}

// CLI11's Range, PositiveNumber and NonNegativeNumber let "nan" through (every comparison with
// NaN is false); these refuse anything but a finite number in [lo, hi].
inline CLI::Validator finiteRange(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        size_t used = 0;
        double v = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          return fmt::format("'{}' is not a number", text);
        }
        if (used != text.size() || !std::isfinite(v)) return fmt::format("'{}' is not a finite number", text);
        if (v < lo || v > hi) return fmt::format("{} is outside [{}, {}]", text, lo, hi);
        return {};
      },
      fmt::format("NUMBER in [{}, {}]", lo, hi));
}
inline CLI::Validator positiveFinite() { return finiteRange(1e-300, 1e300).description("POSITIVE NUMBER"); }
inline CLI::Validator nonNegativeFinite() { return finiteRange(0, 1e300).description("NUMBER >= 0"); }

}  // namespace polyloc::cli
