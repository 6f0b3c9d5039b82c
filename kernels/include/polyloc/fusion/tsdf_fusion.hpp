// A mesh from depth frames with known poses: truncated signed distance fusion (Curless and Levoy
// 1996; KinectFusion's map) in Open3D's ScalableTSDFVolume (a hash of 16^3-voxel blocks: memory
// grows with the surface, not the room), marching cubes, then Open3D's quadric decimation down to
// a triangle budget. Open3D stays behind this interface: nothing else includes it.
//
//   TsdfFusion fusion(config, camera);
//   for each frame: fusion.integrate(depth_m.data(), world_T_body);
//   Mesh map = fusion.extract();
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/sensors/depth_camera.hpp>

#include <memory>

namespace polyloc {

struct FusionConfig {
  double voxel = 0.01;        // m: the grid's cell (1 cm: a Kinect's noise at 1.5 m)
  double truncation = 0.04;   // m: the signed distance's band either side of a surface (3-5 voxels)
  double min_depth = 0.1;     // m: nearer pixels are not fused
  double max_depth = 3.5;     // m: farther pixels are not fused (structured light's error grows with z^2)
  size_t max_triangles = 300000;  // decimate to this many; 0: keep marching cubes' mesh whole
  // Throws std::invalid_argument naming the field when a value is out of its domain.
  void validate() const;
};

struct FusionStats {
  size_t frames = 0;          // integrated
  size_t pixels = 0;          // depth pixels within [min_depth, max_depth] fused
  size_t triangles_marched = 0;  // before decimation
};

class TsdfFusion {
 public:
  // camera: its pinhole (a CameraInfo's, depthCameraFromIntrinsics) and size.
  TsdfFusion(const FusionConfig& config, const DepthCameraSpec& camera);
  ~TsdfFusion();
  TsdfFusion(const TsdfFusion&) = delete;
  TsdfFusion& operator=(const TsdfFusion&) = delete;

  // depth: width x height floats, row-major from the top-left pixel, metres along the optical
  // axis; NaN, 0 or out of [min_depth, max_depth]: none. world_T_body: the camera's body frame
  // (REP-103, x along the optical axis). Throws std::invalid_argument for a non-finite pose.
  void integrate(const float* depth, const Pose& world_T_body);
  // Marching cubes over the fused volume, then decimation to max_triangles. Vertices joined,
  // degenerate and duplicate triangles removed. Empty when nothing was fused.
  Mesh extract();
  const FusionStats& stats() const { return stats_; }

 private:
  struct Volume;
  std::unique_ptr<Volume> volume_;
  FusionConfig config_;
  DepthCameraSpec camera_;
  FusionStats stats_;
};

}  // namespace polyloc
