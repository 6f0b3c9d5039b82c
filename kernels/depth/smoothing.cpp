// Smoothing of the kept depth with OpenCV (see stages.hpp). OpenCV knows nothing of holes, so
// rejected pixels go in as 0 and a smoothed value is only taken where it stays within
// max_change of the raw one: a median or bilateral window that straddles a hole or an edge
// would otherwise pull the pixel towards 0 or the other surface.
#include "stages.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

namespace polyloc::depth_detail {

void smoothDepth(const DepthSmoothing& c, Work& work) {
  if (c.method == "none") return;
  thread_local std::vector<float> in, out;
  const size_t n = work.size();
  in.resize(n);
  out.resize(n);
  for (size_t i = 0; i < n; ++i) in[i] = std::isnan(work.depth[i]) ? 0.f : work.depth[i];
  const cv::Mat src(work.h, work.w, CV_32F, in.data());
  cv::Mat dst(work.h, work.w, CV_32F, out.data());
  if (c.method == "median") cv::medianBlur(src, dst, c.size);
  else cv::bilateralFilter(src, dst, c.size, c.sigma_depth, c.sigma_space, cv::BORDER_REPLICATE);
  const float max_change = static_cast<float>(c.max_change);
  for (size_t i = 0; i < n; ++i)
    if (!std::isnan(work.depth[i]) && std::abs(out[i] - work.depth[i]) <= max_change) work.depth[i] = out[i];
}

}  // namespace polyloc::depth_detail
