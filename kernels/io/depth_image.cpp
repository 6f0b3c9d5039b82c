#include <polyloc/io/depth_image.hpp>

#include <fmt/core.h>

#include <cstring>
#include <limits>

namespace polyloc {

std::string depthImageToMetres(const msg::Image& img, std::vector<float>& out) {
  const bool mm = img.encoding == "16UC1";
  if (!mm && img.encoding != "32FC1") return fmt::format("{} encoding: depth is 32FC1 (m) or 16UC1 (mm)", img.encoding);
  if (img.is_bigendian) return "big-endian image";
  const size_t bytes = mm ? 2 : 4;
  if (img.width == 0 || img.height == 0) return fmt::format("{}x{} pixels", img.width, img.height);
  if (img.step < img.width * bytes) return fmt::format("step {} < {} x width {}", img.step, bytes, img.width);
  if (img.data.size() < size_t(img.step) * img.height)
    return fmt::format("{} bytes of data, {} rows of {} need {}", img.data.size(), img.height, img.step,
                       size_t(img.step) * img.height);
  out.resize(size_t(img.width) * img.height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (uint32_t v = 0; v < img.height; ++v) {
    const uint8_t* row = img.data.data() + size_t(v) * img.step;
    float* dst = out.data() + size_t(v) * img.width;
    for (uint32_t u = 0; u < img.width; ++u) {
      float d;
      if (mm) {
        uint16_t raw;
        std::memcpy(&raw, row + size_t(u) * 2, 2);
        d = raw == 0 ? nan : float(raw) * 1e-3f;
      } else {
        std::memcpy(&d, row + size_t(u) * 4, 4);
        if (!(d > 0)) d = nan;
      }
      dst[u] = d;
    }
  }
  return "";
}

}  // namespace polyloc
