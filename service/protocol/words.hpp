// Data words of a frame: 32-bit values, floats as IEEE-754 binary32 bit patterns, 64-bit values
// as two words (low word first), strings as a byte count and the bytes packed 4 to a word in
// wire order (zero padded). Words are in host order here; frame.cpp makes them little-endian.
#pragma once

#include <bit>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace polyloc::protocol {

class WordWriter {
 public:
  void u32(uint32_t v) { w_.push_back(v); }
  void i32(int32_t v) { w_.push_back(static_cast<uint32_t>(v)); }
  void f32(double v) { w_.push_back(std::bit_cast<uint32_t>(static_cast<float>(v))); }
  void u64(uint64_t v) {
    u32(static_cast<uint32_t>(v));
    u32(static_cast<uint32_t>(v >> 32));
  }
  void i64(int64_t v) { u64(static_cast<uint64_t>(v)); }
  void str(std::string_view s) {
    u32(static_cast<uint32_t>(s.size()));
    for (size_t i = 0; i < s.size(); i += 4) {
      uint32_t v = 0;
      for (size_t k = 0; k < 4 && i + k < s.size(); ++k) v |= uint32_t(uint8_t(s[i + k])) << (8 * k);
      w_.push_back(v);
    }
  }
  const std::vector<uint32_t>& words() const { return w_; }
  std::vector<uint32_t> take() { return std::move(w_); }

 private:
  std::vector<uint32_t> w_;
};

// Reads past the end give 0 and clear ok(), so decoders check once at the end, never throw.
class WordReader {
 public:
  explicit WordReader(std::span<const uint32_t> w) : w_(w) {}
  uint32_t u32() {
    if (i_ >= w_.size()) return ok_ = false, 0;
    return w_[i_++];
  }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  uint64_t u64() {
    const uint64_t lo = u32();
    return lo | uint64_t(u32()) << 32;
  }
  int64_t i64() { return static_cast<int64_t>(u64()); }
  std::string str() {
    const uint32_t n = u32();
    if (n > 4 * remaining()) return ok_ = false, std::string();
    std::string s(n, '\0');
    for (uint32_t k = 0; k < n; ++k) s[k] = char((w_[i_ + k / 4] >> (8 * (k % 4))) & 0xff);
    i_ += (n + 3) / 4;
    return s;
  }
  size_t remaining() const { return w_.size() - i_; }
  bool ok() const { return ok_; }
  // ok() and every word used: the size was exactly right.
  bool done() const { return ok_ && i_ == w_.size(); }

 private:
  std::span<const uint32_t> w_;
  size_t i_ = 0;
  bool ok_ = true;
};

}  // namespace polyloc::protocol
