// What the depth filter takes and gives, as plain buffers (no OpenCV in the interface).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace polyloc {

// One ToF frame, row-major from the top-left pixel, as the camera's Image messages carry it:
// depth along the optical axis in metres (not the range along the ray); NaN, inf, 0 or negative
// mean no measurement. Amplitude and a registered RGB image (3 bytes a pixel) are optional.
struct DepthFrameView {
  int width = 0, height = 0;
  const float* depth = nullptr;
  const float* amplitude = nullptr;  // nullable
  const uint8_t* rgb = nullptr;      // nullable
};

// Why a pixel was dropped: the first stage that rejected it.
enum class DepthReject : uint8_t {
  kKept = 0,
  kNoMeasurement,  // depth NaN, inf, <= 0 in the input
  kRange,          // range along the ray outside [range_min, range_max]
  kAmplitude,      // amplitude below amplitude_min, or NaN
  kJumpEdge,       // flying pixel by the view-ray angle
  kConfidence,     // confidence (eq. 6.4) below the threshold
};
inline constexpr size_t kDepthRejectKinds = 6;
const char* depthRejectName(DepthReject r);  // "kept", "no_measurement", "range", ...

struct DepthFilterResult {
  int width = 0, height = 0;
  std::vector<float> depth;          // filtered (and smoothed) depth; NaN where rejected
  std::vector<uint8_t> valid;        // 1 kept, 0 rejected
  std::vector<DepthReject> reason;   // per pixel
  std::array<size_t, kDepthRejectKinds> count{};  // pixels per DepthReject value (kKept: kept)
  // Kept pixels as points in the base frame (metres), structure of arrays, and their pixel index.
  std::vector<float> x, y, z;
  std::vector<uint32_t> pixel;

  size_t kept() const { return count[0]; }
  size_t rejected(DepthReject r) const { return count[static_cast<size_t>(r)]; }
};

}  // namespace polyloc
