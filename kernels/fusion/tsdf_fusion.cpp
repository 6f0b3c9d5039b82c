#include <polyloc/fusion/tsdf_fusion.hpp>

#include <open3d/camera/PinholeCameraIntrinsic.h>
#include <open3d/geometry/Image.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>
#include <open3d/utility/Logging.h>

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

void FusionConfig::validate() const {
  auto check = [](const char* name, double v, double lo, double hi) {
    if (!(std::isfinite(v) && v >= lo && v <= hi))
      throw std::invalid_argument(fmt::format("fusion: {} = {:g} must be in [{:g}, {:g}]", name, v, lo, hi));
  };
  check("voxel", voxel, 1e-3, 1.0);
  check("truncation", truncation, voxel, 100 * voxel);
  check("min_depth", min_depth, 0.0, 100.0);
  check("max_depth", max_depth, min_depth + 1e-3, 100.0);
}

struct TsdfFusion::Volume {
  open3d::pipelines::integration::ScalableTSDFVolume tsdf;
  open3d::camera::PinholeCameraIntrinsic intrinsic;
  open3d::geometry::RGBDImage frame;  // reused: one frame's buffers
  Volume(double voxel, double truncation)
      : tsdf(voxel, truncation, open3d::pipelines::integration::TSDFVolumeColorType::NoColor) {}
};

TsdfFusion::TsdfFusion(const FusionConfig& config, const DepthCameraSpec& camera) : config_(config), camera_(camera) {
  config_.validate();
  volume_ = std::make_unique<Volume>(config_.voxel, config_.truncation);
  // Open3D's principal point puts pixel centres on integers; polyloc's on half-integers.
  volume_->intrinsic.SetIntrinsics(camera.width, camera.height, camera.fx(), camera.fy(), camera.cx() - 0.5, camera.cy() - 0.5);
  volume_->frame.depth_.Prepare(camera.width, camera.height, 1, 4);  // float metres; no colour (NoColor)
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);  // stdout is for --json
}

TsdfFusion::~TsdfFusion() = default;

void TsdfFusion::integrate(const float* depth, const Pose& world_T_body) {
  const Eigen::Matrix4d m = world_T_body.matrix();
  if (!m.allFinite()) throw std::invalid_argument("fusion: the frame's pose is not finite");
  float* d = volume_->frame.depth_.PointerAs<float>();
  const size_t n = camera_.numBeams();
  size_t used = 0;
  for (size_t i = 0; i < n; ++i) {
    const float z = depth[i];
    const bool ok = z >= config_.min_depth && z <= config_.max_depth;  // false for NaN
    d[i] = ok ? z : 0.f;  // Open3D: 0 is "no depth"
    used += ok;
  }
  // Its extrinsic maps world points into the optical frame.
  const Pose world_T_optical = world_T_body * opticalFromBody().inverse();
  volume_->tsdf.Integrate(volume_->frame, volume_->intrinsic, world_T_optical.inverse().matrix());
  ++stats_.frames;
  stats_.pixels += used;
}

Mesh TsdfFusion::extract() {
  std::shared_ptr<open3d::geometry::TriangleMesh> mesh = volume_->tsdf.ExtractTriangleMesh();
  mesh->RemoveDuplicatedVertices();
  mesh->RemoveDegenerateTriangles();
  mesh->RemoveDuplicatedTriangles();
  mesh->RemoveUnreferencedVertices();
  stats_.triangles_marched = mesh->triangles_.size();
  if (config_.max_triangles > 0 && mesh->triangles_.size() > config_.max_triangles) {
    mesh = mesh->SimplifyQuadricDecimation(int(config_.max_triangles), std::numeric_limits<double>::infinity(), 1.0);
    mesh->RemoveDegenerateTriangles();
    mesh->RemoveUnreferencedVertices();
  }
  Mesh out;
  out.source = "tsdf fusion";
  out.vertices.reserve(mesh->vertices_.size());
  for (const Eigen::Vector3d& v : mesh->vertices_) out.vertices.push_back(v.cast<float>());
  out.triangles.reserve(mesh->triangles_.size());
  for (const Eigen::Vector3i& t : mesh->triangles_) out.triangles.push_back({uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2])});
  out.triangle_label.assign(out.triangles.size(), 0);
  return out;
}

}  // namespace polyloc
