// Internal to kernels/depth: the stages of DepthFilter::apply, each on a frame's working depth
// (row-major, NaN where rejected) and the per-pixel reject reasons. A stage only looks at pixels
// still kept and marks the ones it rejects (depth NaN, reason set); the pipeline is filter.cpp.
#pragma once

#include <polyloc/depth/config.hpp>
#include <polyloc/depth/frame.hpp>

#include <limits>

namespace polyloc::depth_detail {

// The working image of one frame.
struct Work {
  int w = 0, h = 0;
  float* depth = nullptr;
  DepthReject* reason = nullptr;
  size_t size() const { return size_t(w) * size_t(h); }
  void reject(size_t i, DepthReject r) {
    depth[i] = std::numeric_limits<float>::quiet_NaN();
    reason[i] = r;
  }
};

// Copies the frame's depth into `work` and rejects missing measurements, ranges outside
// [range_min, range_max] (range = depth * range_per_depth) and dark or NaN amplitudes.
void checkValidity(const DepthFrameView& frame, const DepthValidity& c, float range_min, float range_max,
                   const float* range_per_depth, Work& work);

// Rejects flying pixels by the angle between neighbour edges and the view ray (mode between or
// any, see JumpEdgeFilter); xn, yn are the pixels' normalised image coordinates.
void rejectJumpEdges(const JumpEdgeFilter& c, const float* xn, const float* yn, Work& work);

// Eq. 6.4 iterated (with slope-aware predictions, see ConfidenceFilter); rejects the pixels
// whose confidence ends below the threshold.
void rejectLowConfidence(const ConfidenceFilter& c, const DepthFrameView& frame, Work& work);

// Median or bilateral smoothing of the kept depth (OpenCV); rejected pixels stay rejected.
void smoothDepth(const DepthSmoothing& c, Work& work);

}  // namespace polyloc::depth_detail
