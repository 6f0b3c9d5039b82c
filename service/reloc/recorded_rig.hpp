// The rig a recording is localised with when the config leaves the scanners to the recording:
// `rig: recorded` (or no rig) makes one planar scanner per LaserScan topic, named after the topic
// and mounted at base_link (kRecordedHeight above it; CARMEN's rear laser turned by 180 deg), and
// one depth camera per 16UC1/32FC1 Image beside a CameraInfo in its namespace, its pinhole from
// the CameraInfo's K and size, at base_link's origin (the base is the camera: data sets of a
// hand-held camera, io/rgbd_dataset.hpp);
// a rig sensor of preset `recorded` keeps its mount and takes its geometry. The geometry is the
// first scan's on the topic (io/recorded_geometry.hpp); later scans that differ from it are
// rejected by the TopicRouter with a message naming both.
#pragma once

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/io/recording.hpp>

#include <functional>
#include <string>
#include <vector>

namespace polyloc::reloc {

inline constexpr double kRecordedHeight = 0.3;  // m: above the floor, below any wall's top
// m: a recorded depth camera's ranges (Kinect, RealSense, ToF: none sees closer or farther)
inline constexpr double kRecordedDepthRange[2] = {0.1, 10.0};

// True when the config's rig needs a recording to be complete.
bool needsRecordedRig(const PolylocConfig& config);

// The config's rig completed from the recording `reader` reads (its messages are consumed).
// Notes what it made into `notes`. Throws std::runtime_error naming the recording when a sensor
// finds no scan (or no usable geometry) on its topic, or the recording has no LaserScan at all.
Rig recordedRig(const PolylocConfig& config, RecordingReader& reader, const std::string& name,
                std::vector<std::string>* notes = nullptr);

// The config with its rig completed from the recording (recordedRig), so that jobs and the
// weighing backend see the finished rig; what was made goes to `log`. A config that needs no
// recording is left as it is.
void completeRecordedRig(PolylocConfig& config, RecordingReader& reader, const std::string& name,
                         const std::function<void(const std::string&)>& log);

// The rig sensor name for a depth image topic: "/depth/cam/image" -> "cam" (the simulator's),
// else its namespace's: "/camera/depth/image_raw" -> "camera_depth".
std::string depthSensorNameForTopic(const std::string& topic);

// The rig sensor name for a scan topic: "/front_laser" -> "front_laser", "/scan/lms" -> "lms",
// "/robot/scan" -> "robot_scan" (the TopicRouter finds it by the same rule).
std::string sensorNameForTopic(const std::string& topic);

}  // namespace polyloc::reloc
