// A number typed on the command line: the whole text must be one finite number, else an error
// that names the argument and quotes what was typed.
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <stdexcept>
#include <string>

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
