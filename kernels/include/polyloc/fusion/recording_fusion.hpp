// `polyloc map fuse`'s engine: the depth frames of a recording (a TUM or 7-Scenes folder, a bag
// with a depth Image, its CameraInfo and /ground_truth poses) fused into a mesh at their poses
// (posed_frames.hpp says which frames and poses; the others are counted, not fused).
#pragma once

#include <polyloc/fusion/posed_frames.hpp>
#include <polyloc/fusion/tsdf_fusion.hpp>
#include <polyloc/io/recording.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace polyloc {

struct RecordingFusionStats : PosedFrameStats {
  size_t fused = 0;          // frames integrated (the frames delivered)
  std::vector<Pose> path;    // world_T_body of the frames fused
  FusionStats fusion;
};

// Throws std::runtime_error naming the recording when it has no depth image with a camera info.
// progress(fraction of the recording's messages read), from this thread. An empty mesh when no
// frame was fused.
Mesh fuseRecording(RecordingReader& reader, const std::string& name, const FusionConfig& config,
                   const FrameSelection& selection, RecordingFusionStats& stats,
                   const std::function<void(double)>& progress = {});

}  // namespace polyloc
