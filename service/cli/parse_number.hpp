// A number typed on the command line: the whole text must be one finite number, else an error
// that names the argument and quotes what was typed.
#pragma once

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

}  // namespace polyloc::cli
