// Bad input to the depth filter: NaN, inf, zero and negative depth, NaN amplitude, wrong frame
// sizes, missing buffers. Pixels are rejected and counted; frames that cannot fit are errors.
#include "depth_fixtures.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_depth_input {

using namespace polyloc;
using test::view;

TEST(DepthInput, BadPixelsAreRejectedAndCounted) {
  const DepthCameraSpec cam = pmdO3D100();
  const DepthFilter f(cam, Pose());
  std::vector<float> depth = test::flatDepth(cam, 2.f), amplitude(cam.numBeams(), 100.f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  depth[100] = nan, depth[200] = inf, depth[300] = -inf, depth[400] = 0.f, depth[500] = -1.f;
  depth[600] = 50.f;                    // beyond range_max (7.5 m)
  depth[700] = 0.05f;                   // closer than range_min (0.1 m)
  amplitude[800] = nan;
  DepthFilterResult r;
  f.apply(view(cam, depth, &amplitude), r);
  for (size_t i : {100, 200, 300, 400, 500}) EXPECT_EQ(r.reason[i], DepthReject::kNoMeasurement) << i;
  EXPECT_EQ(r.reason[600], DepthReject::kRange);
  EXPECT_EQ(r.reason[700], DepthReject::kRange);
  EXPECT_EQ(r.reason[800], DepthReject::kAmplitude);
  EXPECT_EQ(r.rejected(DepthReject::kNoMeasurement), 5u);
  EXPECT_EQ(r.rejected(DepthReject::kRange), 2u);
  EXPECT_EQ(r.rejected(DepthReject::kAmplitude), 1u);
  for (size_t i = 0; i < r.depth.size(); ++i) EXPECT_EQ(std::isnan(r.depth[i]), !r.valid[i]) << i;
  for (float z : r.z) EXPECT_TRUE(std::isfinite(z));
  size_t total = 0;
  for (size_t c : r.count) total += c;
  EXPECT_EQ(total, cam.numBeams());
}

TEST(DepthInput, AllInvalidFrameGivesNoPoints) {
  const DepthCameraSpec cam = pmdO3D100();
  const DepthFilter f(cam, Pose());
  const std::vector<float> depth(cam.numBeams(), std::numeric_limits<float>::quiet_NaN());
  DepthFilterResult r;
  f.apply(view(cam, depth), r);
  EXPECT_EQ(r.kept(), 0u);
  EXPECT_TRUE(r.x.empty());
  EXPECT_EQ(r.rejected(DepthReject::kNoMeasurement), cam.numBeams());
}

TEST(DepthInput, WrongSizeOrMissingBufferIsAnError) {
  const DepthCameraSpec cam = pmdO3D100();
  const DepthFilter f(cam, Pose());
  const std::vector<float> small(10, 2.f);
  DepthFilterResult r;
  try {
    f.apply({5, 2, small.data()}, r);
    FAIL() << "no error for a 5x2 frame";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("5x2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("64x50"), std::string::npos) << e.what();
  }
  EXPECT_THROW(f.apply({cam.width, cam.height, nullptr}, r), std::invalid_argument);
  const std::vector<float> depth = test::flatDepth(cam, 2.f);
  std::vector<DepthFrameView> frames = {view(cam, depth), {5, 2, small.data()}};
  std::vector<DepthFilterResult> out(2);
  EXPECT_THROW(f.applyBatch(frames, out), std::invalid_argument);
  std::vector<DepthFilterResult> one(1);
  EXPECT_THROW(f.applyBatch(std::span(frames).first(1), std::span(out).first(0)), std::invalid_argument);
  f.applyBatch(std::span(frames).first(1), one);
  EXPECT_EQ(one[0].kept(), cam.numBeams());
}

TEST(DepthInput, SettingsThatCannotWorkAreErrors) {
  const DepthCameraSpec cam = pmdO3D100();
  DepthFilterConfig c;
  c.smoothing.size = 4;
  EXPECT_THROW(DepthFilter(cam, Pose(), c), std::invalid_argument);
  c = {};
  c.jump_edge.neighbours = 6;
  EXPECT_THROW(DepthFilter(cam, Pose(), c), std::invalid_argument);
  DepthCameraSpec empty = cam;
  empty.width = 0;
  EXPECT_THROW(DepthFilter(empty, Pose()), std::invalid_argument);
}

}  // namespace polyloc::t_depth_input
