// The depth frames of a recording with their poses, for what needs both (fusion, evaluation): the
// first 16UC1/32FC1 Image topic beside a CameraInfo in its namespace (the first by name), its
// camera from the first CameraInfo, each frame's pose the /ground_truth at its stamp or
// interpolated between the two samples around it when both lie within 50 ms. Frames without a
// pose, of another size or encoding, are counted with a reason, not delivered.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/sensors/depth_camera.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace polyloc {

// Which depth frames, by their index in the recording (0, 1, ...): first..last (inclusive;
// last < 0: to the end), every step-th from first, and of those only even or odd indices.
struct FrameSelection {
  int64_t first = 0, last = -1;
  int64_t step = 1;
  enum class Parity { All, Even, Odd } parity = Parity::All;
  bool picks(int64_t index) const;
  // "all", "even", "odd", or "FIRST:LAST[:STEP]" (LAST may be empty: to the end). Throws
  // std::invalid_argument naming the text.
  static FrameSelection parse(const std::string& text);
};

struct PosedFrame {
  int64_t index = 0, stamp_ns = 0;
  const std::vector<float>& depth;  // metres along the optical axis, row-major; NaN: none
  Pose world_T_body;                // REP-103 body frame of the camera
};

struct PosedFrameStats {
  std::string image_topic;        // the depth topic read
  DepthCameraSpec camera;         // from its CameraInfo
  size_t images = 0;              // depth frames on that topic
  size_t selected = 0;            // picked by the selection
  size_t delivered = 0;           // with a pose, handed to the callback
  size_t without_pose = 0, bad_images = 0;
  std::map<std::string, size_t> reasons;  // why frames were not delivered, with counts
  std::vector<std::string> warnings;      // the first 20, naming the frame
};

// Calls `frame` for each selected frame with a pose, in order. The camera's ranges are
// range_min..range_max. Throws std::runtime_error naming the recording when it has no depth
// Image beside a CameraInfo, or a CameraInfo that is no pinhole. progress(fraction of messages).
void forEachPosedFrame(RecordingReader& reader, const std::string& name, const FrameSelection& selection,
                       double range_min, double range_max, PosedFrameStats& stats,
                       const std::function<void(const PosedFrame&)>& frame,
                       const std::function<void(double)>& progress = {});

}  // namespace polyloc
