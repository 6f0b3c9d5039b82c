// Decimal seconds as text <-> int64 nanoseconds, exactly: a double holds only ~16 digits, and
// "1305031102.175304123" needs 19, so the integer and fraction parts are parsed separately.
// Private to kernels/io (TUM and CARMEN both store time as decimal seconds).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

namespace polyloc::io_detail {

// "12.5" -> 12500000000. Accepts a sign, digits, an optional fraction (digits past the 9th are
// rounded) and, rarely used, an exponent (then via double). Empty, non-numeric, non-finite or
// out-of-range text gives nullopt.
inline std::optional<int64_t> parseSecondsNs(std::string_view s) {
  if (s.empty()) return std::nullopt;
  if (s.find_first_of("eE") != std::string_view::npos) {
    double v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v) || std::fabs(v) > 9.2e9)
      return std::nullopt;
    return static_cast<int64_t>(std::llround(v * 1e9));
  }
  bool negative = false;
  size_t i = 0;
  if (s[0] == '-' || s[0] == '+') negative = s[0] == '-', i = 1;
  int64_t whole = 0, frac = 0;
  int whole_digits = 0, frac_digits = 0;
  for (; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i, ++whole_digits) {
    if (whole > 922337203) return std::nullopt;  // * 1e9 would overflow int64
    whole = whole * 10 + (s[i] - '0');
  }
  if (whole > 9223372035) return std::nullopt;
  bool round_up = false;
  if (i < s.size() && s[i] == '.') {
    for (++i; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i, ++frac_digits) {
      if (frac_digits < 9)
        frac = frac * 10 + (s[i] - '0');
      else if (frac_digits == 9)
        round_up = s[i] >= '5';
    }
  }
  if (i != s.size() || whole_digits + frac_digits == 0) return std::nullopt;
  for (int d = frac_digits; d < 9; ++d) frac *= 10;
  int64_t ns = whole * 1000000000 + frac + (round_up ? 1 : 0);
  return negative ? -ns : ns;
}

// 12500000000 -> "12.500000000": always nine decimals, no rounding through double.
inline std::string formatSecondsNs(int64_t ns) {
  const bool negative = ns < 0;
  const uint64_t a = negative ? uint64_t(0) - uint64_t(ns) : uint64_t(ns);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%s%llu.%09llu", negative ? "-" : "",
                static_cast<unsigned long long>(a / 1000000000),
                static_cast<unsigned long long>(a % 1000000000));
  return buf;
}

}  // namespace polyloc::io_detail
