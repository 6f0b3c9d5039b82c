// Meshes from depth frames (fusion/): depth images cast in a known room, fused at their poses,
// give a mesh on the room's walls, facing the camera; frames are picked and paired with their
// poses as documented; bad input is counted.
#include <polyloc/fusion/recording_fusion.hpp>
#include <polyloc/fusion/tsdf_fusion.hpp>
#include <polyloc/io/memory_recording.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/raycast/factory.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace polyloc::t_tsdf_fusion {
namespace {

// A 4 x 3 x 2.5 m room: walls 0.2 m thick around [-2, 2] x [-1.5, 1.5] x [0, 2.5].
Mesh room() {
  Mesh m;
  m.addBox({-2.2, -1.7, -0.2}, {2.2, 1.7, 0}, 1);   // floor
  m.addBox({-2.2, -1.7, 2.5}, {2.2, 1.7, 2.7}, 1);  // ceiling
  m.addBox({-2.2, -1.7, 0}, {-2.0, 1.7, 2.5}, 1);
  m.addBox({2.0, -1.7, 0}, {2.2, 1.7, 2.5}, 1);
  m.addBox({-2.0, -1.7, 0}, {2.0, -1.5, 2.5}, 1);
  m.addBox({-2.0, 1.5, 0}, {2.0, 1.7, 2.5}, 1);
  return m;
}

// Distance of a point inside the room to its nearest surface.
double toSurface(const Eigen::Vector3f& p) {
  return std::min({2.0 - std::abs(p.x()), 1.5 - std::abs(p.y()), double(p.z()), 2.5 - p.z()});
}

const DepthCameraSpec kCamera = depthCameraFromIntrinsics(160, 120, 120, 120, 79.5, 59.5, 0.1, 10, 30);

// The camera turning on the spot at 1.2 m, looking 15 deg down, frame i of n.
Pose cameraPose(int i, int n) { return Pose::fromXYZRPY(0.3, -0.2, 1.2, 0, 0.26, 2 * M_PI * i / n); }

std::vector<float> depthAt(const RayCaster& caster, const Pose& pose) {
  const BeamSet beams = kCamera.beams();
  std::vector<float> range(beams.size()), depth(beams.size());
  caster.castScans(std::span<const Pose>(&pose, 1), beams, {range.data()});
  const std::vector<float> factor = kCamera.depthFactors();
  for (size_t b = 0; b < range.size(); ++b) depth[b] = std::isfinite(range[b]) ? range[b] * factor[b] : NAN;
  return depth;
}

TEST(TsdfFusion, KnownRoomGivesWallsWithinAVoxelFacingTheCamera) {
  const Mesh truth = room();
  const auto caster = makeCaster("embree", truth);
  FusionConfig cfg;
  cfg.voxel = 0.02, cfg.truncation = 0.08, cfg.max_depth = 6.0, cfg.max_triangles = 20000;
  TsdfFusion fusion(cfg, kCamera);
  const int n = 24;
  for (int i = 0; i < n; ++i) fusion.integrate(depthAt(*caster, cameraPose(i, n)).data(), cameraPose(i, n));
  const Mesh fused = fusion.extract();
  EXPECT_EQ(fusion.stats().frames, size_t(n));
  EXPECT_GT(fusion.stats().triangles_marched, fused.numTriangles());
  ASSERT_GT(fused.numTriangles(), 1000u);
  EXPECT_LE(fused.numTriangles(), cfg.max_triangles);
  // Every vertex on a wall, floor or ceiling: within a voxel (decimation keeps planes planar).
  double worst = 0;
  for (const Eigen::Vector3f& v : fused.vertices) worst = std::max(worst, toSurface(v));
  EXPECT_LT(worst, cfg.voxel) << "a fused vertex is off the room's surfaces";
  // The walls the camera saw all round are there: the mesh spans the room.
  const Eigen::AlignedBox3f b = fused.bounds();
  EXPECT_NEAR(b.min().x(), -2.0, 0.05);
  EXPECT_NEAR(b.max().x(), 2.0, 0.05);
  EXPECT_NEAR(b.min().y(), -1.5, 0.05);
  EXPECT_NEAR(b.max().y(), 1.5, 0.05);

  // Cast into the fused mesh from a new pose: the ranges are the room's, and the surfaces face
  // the camera (front faces: polyloc's casters take a back face for the inside of a solid).
  const auto fused_caster = makeCaster("embree", fused);
  const Pose probe = cameraPose(5, 48);  // between two fused frames
  const BeamSet beams = kCamera.beams();
  std::vector<float> want(beams.size()), got(beams.size()), nx(beams.size()), ny(beams.size()), nz(beams.size());
  caster->castScans(std::span<const Pose>(&probe, 1), beams, {want.data()});
  fused_caster->castScans(std::span<const Pose>(&probe, 1), beams, {got.data(), nullptr, nullptr, nx.data(), ny.data(), nz.data()});
  size_t close = 0, facing = 0, hits = 0;
  for (size_t b = 0; b < beams.size(); ++b) {
    if (!std::isfinite(got[b])) continue;
    ++hits;
    close += std::abs(got[b] - want[b]) < 0.03f;
    const Eigen::Vector3d dir = probe.rotate(Eigen::Vector3d(beams.dx[b], beams.dy[b], beams.dz[b]));
    facing += dir.dot(Eigen::Vector3d(nx[b], ny[b], nz[b])) < 0;
  }
  EXPECT_GT(hits, beams.size() * 95 / 100);
  EXPECT_GT(close, hits * 97 / 100);
  EXPECT_GT(facing, hits * 99 / 100);
}

TEST(TsdfFusion, RecordingFramesPairWithTheirPosesAndBadOnesAreCounted) {
  const Mesh truth = room();
  const auto caster = makeCaster("embree", truth);
  auto msgs = std::make_shared<std::vector<RecordedMessage>>();
  const int n = 12;
  msg::CameraInfo info;
  info.width = 160, info.height = 120;
  info.k = {120, 0, 79.5, 0, 120, 59.5, 0, 0, 1};
  for (int i = 0; i < n; ++i) {
    const int64_t t = 1'000'000'000 + i * 100'000'000;
    const std::vector<float> d = depthAt(*caster, cameraPose(i, n));
    msg::Image img;
    img.header.stamp = msg::fromNs(t);
    img.width = 160, img.height = 120, img.encoding = "32FC1", img.step = 640;
    img.data.resize(d.size() * 4);
    std::memcpy(img.data.data(), d.data(), img.data.size());
    if (i == 3) img.encoding = "8UC1";  // bad
    if (i == 4) img.width = 80;         // wrong size
    msgs->push_back({"/cam/camera_info", t, t, info});
    msgs->push_back({"/cam/depth", t, t, img});
    // Truth at the frame's stamp, except frame 6 (none within 50 ms) and frame 7 (between two
    // samples 40 ms around it: interpolated).
    msg::PoseStamped p;
    if (i == 7) {
      for (int64_t dt : {-20'000'000, 20'000'000}) {
        p.header.stamp = msg::fromNs(t + dt);
        p.pose = toMsgPose(Pose::interpolate(cameraPose(i, n), cameraPose(i + (dt > 0 ? 1 : -1), n), 0.2));
        msgs->push_back({"/ground_truth", t + dt, t + dt, p});
      }
    } else if (i != 6) {
      p.header.stamp = msg::fromNs(t);
      p.pose = toMsgPose(cameraPose(i, n));
      msgs->push_back({"/ground_truth", t, t, p});
    }
  }
  auto reader = readMemory(msgs);
  FusionConfig cfg;
  cfg.voxel = 0.04, cfg.truncation = 0.12, cfg.max_depth = 6.0;
  RecordingFusionStats st;
  double last_progress = 0;
  const Mesh m = fuseRecording(*reader, "test", cfg, FrameSelection::parse("all"), st, [&](double f) { last_progress = f; });
  EXPECT_EQ(st.image_topic, "/cam/depth");
  EXPECT_EQ(st.images, size_t(n));
  EXPECT_EQ(st.bad_images, 2u);
  EXPECT_EQ(st.without_pose, 1u);
  EXPECT_EQ(st.fused, size_t(n - 3));
  EXPECT_EQ(last_progress, 1.0);
  ASSERT_GT(m.numTriangles(), 100u);
  // Frame 7's pose: the midpoint of its two samples.
  ASSERT_EQ(st.path.size(), size_t(n - 3));
  const Pose mid = Pose::interpolate(Pose::interpolate(cameraPose(7, n), cameraPose(6, n), 0.2),
                                     Pose::interpolate(cameraPose(7, n), cameraPose(8, n), 0.2), 0.5);
  EXPECT_LT((st.path[4].translation() - mid.translation()).norm(), 1e-9);

  // Even frames only; a range with a step.
  auto again = readMemory(msgs);
  RecordingFusionStats even;
  fuseRecording(*again, "test", cfg, FrameSelection::parse("even"), even);
  EXPECT_EQ(even.selected, size_t(n / 2));
  EXPECT_EQ(even.fused, size_t(n / 2 - 2));  // 4 bad, 6 without a pose
  const FrameSelection s = FrameSelection::parse("2:8:3");
  EXPECT_TRUE(s.picks(2) && s.picks(5) && s.picks(8));
  EXPECT_FALSE(s.picks(1) || s.picks(3) || s.picks(11));
  EXPECT_TRUE(FrameSelection::parse("10:").picks(1000));
  for (const char* bad : {"", "1", "odds", "5:2", "1:2:0", "-1:4", "a:b", "1:2:3:4"})
    EXPECT_THROW(FrameSelection::parse(bad), std::invalid_argument) << bad;
  FusionConfig huge = cfg;
  huge.voxel = 1e19;
  EXPECT_THROW(TsdfFusion(huge, kCamera), std::invalid_argument);
}

}  // namespace
}  // namespace polyloc::t_tsdf_fusion
