// Depth-camera data sets read as recordings: a folder of 16-bit depth images with the camera's
// poses, in the layouts of the TUM RGB-D benchmark (depth.txt, depth/*.png at 5000 per metre,
// groundtruth.txt) and of Microsoft 7-Scenes (frame-NNNNNN.depth.png in mm, frame-NNNNNN.pose.txt,
// camera-intrinsics.txt). openRecording() recognises both; every command that reads a recording
// reads them. Each frame becomes, at its stamp:
//   /depth/camera/camera_info  sensor_msgs/CameraInfo (K as calibrated, pixel centres on integers)
//   /depth/camera/image        sensor_msgs/Image, 32FC1 depth along the optical axis in metres,
//                              NaN where the camera gave none (0, and 65535 in 7-Scenes)
//   /ground_truth              geometry_msgs/PoseStamped: the camera's body frame (REP-103: x
//                              forward, y left, z up; the data sets give the optical frame, x right,
//                              y down, z forward) in the data set's world, where the frame has one
// The rig is the camera alone at the base's origin (`rig: recorded`, service/reloc/recorded_rig).
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/sensors/depth_camera.hpp>  // opticalFromBody

#include <memory>
#include <optional>
#include <string>

namespace polyloc {

inline constexpr const char* kRgbdImageTopic = "/depth/camera/image";
inline constexpr const char* kRgbdInfoTopic = "/depth/camera/camera_info";

struct RgbdIntrinsics {
  double fx = 525.0, fy = 525.0;   // pixels
  double cx = 319.5, cy = 239.5;   // pixels, ROS convention (the first pixel's centre is 0)
  double depth_scale = 5000.0;     // image units per metre (TUM 5000, 7-Scenes and Kinect mm 1000)
  double rate_hz = 30.0;           // frame rate where the data set has no stamps (7-Scenes)
  std::string source;              // where the values came from, for the reader's notes
};

// Defaults of the layouts, named in docs/recordings.md. TUM: the benchmark's calibrated depth
// intrinsics of freiburg1, 2 or 3 when the folder's name says which (rgbd_dataset_freiburg2_...),
// else ROS's default Kinect (525, 525, 319.5, 239.5); 7-Scenes: its published 585, 585, 320, 240, mm.
RgbdIntrinsics tumIntrinsics(const std::string& folder);
RgbdIntrinsics sevenScenesIntrinsics();

// A small YAML file overriding the defaults: fx, fy, cx, cy (all four or none), depth_scale,
// rate_hz. Unknown keys and bad values throw ConfigError naming file:line:key.
RgbdIntrinsics loadIntrinsics(const std::string& yaml_file, RgbdIntrinsics defaults);

// Whether a folder holds either layout (by its files, not its name).
bool isSevenScenes(const std::string& dir);
bool isTumRgbd(const std::string& dir);

// The readers. `intrinsics_file`: a YAML as above; without one, `intrinsics.yaml` in the folder
// is read where there is one, then the layout's own (7-Scenes camera-intrinsics.txt), then the
// defaults. Throws IoError when the folder has no readable frame.
std::unique_ptr<RecordingReader> openSevenScenes(const std::string& dir, const std::string& intrinsics_file = "");
std::unique_ptr<RecordingReader> openTumRgbd(const std::string& dir, const std::string& intrinsics_file = "");

}  // namespace polyloc
