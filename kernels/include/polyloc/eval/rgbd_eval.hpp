// `polyloc eval rgbd`: a real depth sequence (TUM RGB-D, 7-Scenes, a bag with a depth camera and
// /ground_truth) judged against a mesh of the same place: without a map, one fused from the even
// frames (fusion/) and the odd frames evaluated; with one, every frame. Per evaluated frame:
//  - the agreement floor: the frame's pixels aligned to the mesh from the ground truth by 6-DoF
//    point-to-plane ICP (mcl/refine); how far the refined pose lands from the ground truth is how
//    far ground truth and mesh disagree, which no localiser judged by the ground truth can beat;
//  - the depth filter (depth/) against labels from the mesh rendered at the ground truth: a pixel
//    is good when its depth is within DepthTolerance::at(z) of the rendered one; ambiguous when
//    not, but a rendered pixel within align_px of it agrees (a depth edge the ground truth's own
//    error moves by a pixel or two); an outlier when no rendered depth within align_px agrees;
//    unlabelled where the mesh has no surface. The precision and recall of the pixels each stage
//    removes, over the good and outlier pixels.
#pragma once

#include <polyloc/depth/config.hpp>
#include <polyloc/eval/depth_quality.hpp>
#include <polyloc/fusion/recording_fusion.hpp>
#include <polyloc/mcl/config.hpp>

#include <functional>
#include <string>
#include <vector>

namespace polyloc {

// Outlier tolerance of a structured-light depth at z: the mesh's and the ground truth's own error
// (base) plus three standard deviations of a Kinect's depth noise, 1.6e-3 z^2 m (Khoshelham and
// Elberink 2012: about 4 cm at 5 m): 3 cm + 4.8 mm at 1 m, + 19 mm at 2 m, + 43 mm at 3 m.
struct DepthTolerance {
  double base = 0.03;     // m
  double per_m2 = 0.0048; // m per m^2 of depth
  int align_px = 2;       // pixels the ground truth's rendered edges may be off
  double at(double z) const { return base + per_m2 * z * z; }
};

struct RgbdEvalOptions {
  std::string map;                    // mesh; "": fused from the even frames, the odd ones evaluated
  FusionConfig fusion;                // when fusing
  std::string frames;                 // which frames to evaluate; "": odd when fusing, else all
  DepthFilterConfig filter;
  DepthTolerance tolerance;
  RefineConfig floor_refine = floorRefineDefaults();  // the floor's ICP
  size_t floor_every = 1;             // the floor on every n-th evaluated frame (it casts a lot)
  int64_t sample_frame = -1;          // the frame kept whole for a picture; -1: the first evaluated past the middle
  std::function<void(const std::string& stage, double fraction)> progress;
  static RefineConfig floorRefineDefaults();  // 6-DoF, no search, 2000 pixels, 30 iterations
};

enum class RgbdLabel : uint8_t { kNone = 0, kGood, kOutlier, kAmbiguous, kUnlabelled };

struct RgbdFrameResult {
  int64_t index = 0, stamp_ns = 0;
  Pose truth;
  bool floor_ok = false;
  double floor_translation = 0, floor_rotation = 0;  // m, rad: ICP from the truth vs the truth
  double floor_rms = 0;                               // m, its point-to-plane residual
  size_t outliers = 0, good = 0, ambiguous = 0, unlabelled = 0;  // pixels with a measurement
};

struct RgbdFilterStage {
  std::string name;  // "range", "jump_edge", "confidence", "filter" (all stages together)
  uint64_t removed = 0, removed_outliers = 0, removed_good = 0;  // labelled pixels it removed first
  uint64_t outliers = 0;                                          // labelled outliers in all
  double precision() const { return removed_outliers + removed_good ? double(removed_outliers) / double(removed_outliers + removed_good) : 1.0; }
  double recall() const { return outliers ? double(removed_outliers) / double(outliers) : 1.0; }
};

struct RgbdEvalResult {
  std::string input, map;
  bool fused = false;
  RecordingFusionStats fusion;        // when fused
  size_t map_triangles = 0;
  DepthCameraSpec camera;
  std::vector<RgbdFrameResult> frames;
  // The floor over the frames it was computed on: RMSE translation (m) and rotation (rad).
  size_t floor_frames = 0, floor_failed = 0;
  double floor_rmse_translation = 0, floor_rmse_rotation = 0;
  std::vector<RgbdFilterStage> filter;  // per stage, then "filter" (the whole chain)
  double filter_seconds = 0;          // the filter's own time over all frames
  // One frame whole (RgbdEvalOptions::sample_frame), row-major: measured and rendered depth (m,
  // NaN: none), the label of each pixel (RgbdLabel), the filter's verdict (1 kept).
  struct Sample {
    int64_t index = -1;
    std::vector<float> measured, rendered;
    std::vector<uint8_t> label, kept;
  } sample;
  uint64_t outliers = 0, good = 0, ambiguous = 0, unlabelled = 0;
};

// Throws std::runtime_error naming the input when it has no depth frames with ground truth, or
// the map cannot be loaded or fused.
RgbdEvalResult evaluateRgbd(const std::string& input, const RgbdEvalOptions& options);

}  // namespace polyloc
