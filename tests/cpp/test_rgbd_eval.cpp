// polyloc eval rgbd's measurements on a data set whose truth is known: a TUM folder written
// here from depth images cast in a known room, with isolated outlier pixels planted. The floor
// is zero (ground truth and mesh agree), the planted pixels are the outliers the labels find,
// and the filter removes them.
#include <polyloc/eval/rgbd_eval.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/factory.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <fstream>

namespace polyloc::t_rgbd_eval {
namespace {

namespace fs = std::filesystem;

TEST(RgbdEval, KnownRoomGivesZeroFloorAndFindsThePlantedOutliers) {
  test::TempDir tmp;
  Mesh room;
  const uint32_t wall = room.labelId("wall");
  room.addBox({-2.2, -1.7, -0.2}, {2.2, 1.7, 0}, wall);
  room.addBox({-2.2, -1.7, 2.5}, {2.2, 1.7, 2.7}, wall);
  room.addBox({-2.2, -1.7, 0}, {-2.0, 1.7, 2.5}, wall);
  room.addBox({2.0, -1.7, 0}, {2.2, 1.7, 2.5}, wall);
  room.addBox({-2.0, -1.7, 0}, {2.0, -1.5, 2.5}, wall);
  room.addBox({-2.0, 1.5, 0}, {2.0, 1.7, 2.5}, wall);
  room.addBox({0.8, 0.5, 0}, {1.4, 1.5, 0.9}, wall);  // a cabinet: edges to label
  saveMesh(room, tmp.file("room.ply"));
  const auto caster = makeCaster("embree", room);

  const fs::path dir = tmp.path() / "tum";
  fs::create_directories(dir / "depth");
  std::ofstream(dir / "intrinsics.yaml") << "fx: 120\nfy: 120\ncx: 79.5\ncy: 59.5\n";
  const DepthCameraSpec cam = depthCameraFromIntrinsics(160, 120, 120, 120, 79.5, 59.5, 0.1, 10, 30);
  const BeamSet beams = cam.beams();
  const std::vector<float> factor = cam.depthFactors();
  std::ofstream list(dir / "depth.txt"), truth(dir / "groundtruth.txt");
  const int frames = 6, planted_per_frame = 40;
  for (int i = 0; i < frames; ++i) {
    const Pose body = Pose::fromXYZRPY(-0.5 + 0.1 * i, -0.3, 1.3, 0.02, 0.3, 0.4 + 0.15 * i);
    std::vector<float> range(beams.size());
    caster->castScans(std::span<const Pose>(&body, 1), beams, {range.data()});
    cv::Mat png(120, 160, CV_16UC1, cv::Scalar(0));
    for (size_t b = 0; b < range.size(); ++b)
      if (std::isfinite(range[b])) png.at<uint16_t>(int(b / 160), int(b % 160)) = uint16_t(std::lround(range[b] * factor[b] * 5000));
    // Isolated pixels 0.5 m behind their surface, on a grid away from edges and each other.
    for (int k = 0; k < planted_per_frame; ++k) {
      const int u = 12 + (k % 8) * 18, v = 12 + (k / 8) * 21 + i;
      png.at<uint16_t>(v, u) = uint16_t(png.at<uint16_t>(v, u) + 2500);
    }
    cv::imwrite((dir / "depth" / (std::to_string(i) + ".png")).string(), png);
    const std::string stamp = std::to_string(100 + i) + ".000000";
    list << stamp << " depth/" << i << ".png\n";
    const Pose optical = body * opticalFromBody().inverse();
    const Eigen::Quaterniond q = optical.rotation();
    truth << stamp << ' ' << optical.x() << ' ' << optical.y() << ' ' << optical.z() << ' ' << q.x() << ' ' << q.y()
          << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  list.close(), truth.close();

  RgbdEvalOptions o;
  o.map = tmp.file("room.ply");
  o.tolerance.align_px = 1;
  const RgbdEvalResult r = evaluateRgbd(dir.string(), o);
  ASSERT_EQ(r.frames.size(), size_t(frames));
  EXPECT_EQ(r.floor_frames, size_t(frames));
  // Depth quantised to 0.2 mm, stamps exact: ICP from the truth stays on it.
  EXPECT_LT(r.floor_rmse_translation, 0.002);
  EXPECT_LT(r.floor_rmse_rotation, 0.002);
  // The planted pixels, and only they (a planted pixel on the cabinet's rim may be ambiguous).
  EXPECT_GE(r.outliers, uint64_t(frames * planted_per_frame * 9 / 10));
  EXPECT_LE(r.outliers, uint64_t(frames * planted_per_frame));
  EXPECT_GT(r.good, uint64_t(frames * 160 * 120 * 9 / 10));
  const RgbdFilterStage& all = r.filter.back();
  EXPECT_EQ(all.name, "filter");
  EXPECT_EQ(all.outliers, r.outliers);
  EXPECT_GE(all.recall(), 0.9) << all.removed_outliers << " of " << all.outliers;
  EXPECT_GE(all.precision(), 0.5) << all.removed_good << " good pixels removed";
}

}  // namespace
}  // namespace polyloc::t_rgbd_eval
