// The depth filter on synthetic frames of known geometry: points in the base frame, flying
// pixels at a step edge, isolated outliers under the confidence filter, smoothing.
#include "depth_fixtures.hpp"

#include <polyloc/geometry/random.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_depth_filter {

using namespace polyloc;
using test::view;


DepthFilterConfig rejectOnly() {
  DepthFilterConfig c;
  c.smoothing.method = "none";
  return c;
}

// Left half at `near`, right half at `far`; column `mixed_u` at `mixed` (a flying pixel column).
std::vector<float> stepEdge(const DepthCameraSpec& cam, float near, float far, int mixed_u, float mixed) {
  std::vector<float> d(cam.numBeams());
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) d[size_t(v) * cam.width + u] = u == mixed_u ? mixed : u < cam.width / 2 ? near : far;
  return d;
}


TEST(DepthFilter, WallInFrontGivesBasePointsAtItsDistance) {
  const DepthCameraSpec cam = pmdO3D100();
  const Pose mount = Pose::fromXYZRPY(0.3, 0.1, 0.75, 0, 0, 0);  // looking along base x
  const DepthFilter f(cam, mount, rejectOnly());
  const std::vector<float> depth = test::flatDepth(cam, 2.0f);
  DepthFilterResult r;
  f.apply(view(cam, depth), r);
  ASSERT_EQ(r.kept(), cam.numBeams());
  ASSERT_EQ(r.x.size(), cam.numBeams());
  for (size_t k = 0; k < r.x.size(); ++k) EXPECT_NEAR(r.x[k], 2.3f, 1e-5f);
  // The corners of the image span the field of view: tan(20 deg) * 2 m to the sides.
  const float half_w = 2.0f * std::tan(0.5f * float(cam.hfov_rad)) * (1.f - 1.f / cam.width);
  EXPECT_NEAR(r.y[0], 0.1f + half_w, 1e-4f);               // top-left pixel: left (+y) ...
  EXPECT_GT(r.z[0], 0.75f);                                // ... and up
  EXPECT_NEAR(r.y[cam.width - 1], 0.1f - half_w, 1e-4f);   // top-right: right
}

TEST(DepthFilter, FloorSeenByAPitchedCameraLiesAtZeroHeight) {
  const DepthCameraSpec cam = pmdO3D100();
  const Pose mount = Pose::fromXYZRPY(0.3, 0, 0.75, 0, deg2rad(20), 0);  // pitched 20 deg down
  // Range to the floor z = 0 along each ray; rays that miss it see a wall 4 m ahead.
  const std::vector<float> depth = test::depthImage(cam, mount, [&](int, int, const Eigen::Vector3d& ray) {
    const double to_floor = ray.z() < 0 ? -0.75 / ray.z() : 1e9;
    const double to_wall = (4.0 - 0.3) / ray.x();
    return float(std::min(to_floor, to_wall));
  });
  const DepthFilter f(cam, mount, rejectOnly());
  DepthFilterResult r;
  f.apply(view(cam, depth), r);
  size_t floor = 0;
  for (size_t k = 0; k < r.x.size(); ++k) {
    if (r.x[k] < 3.95f) {
      EXPECT_NEAR(r.z[k], 0.f, 1e-4f) << "pixel " << r.pixel[k];
      ++floor;
    } else {
      EXPECT_NEAR(r.x[k], 4.f, 1e-4f);
    }
  }
  EXPECT_GT(floor, cam.numBeams() / 2);
  // Only the floor-wall corner may be lost (a crease, not an outlier): nearly everything is kept.
  EXPECT_GT(r.kept(), cam.numBeams() * 95 / 100);
}

TEST(DepthFilter, FlyingPixelsAtAStepEdgeAreRemoved) {
  const DepthCameraSpec cam = pmdO3D100();
  const int edge = cam.width / 2;
  const std::vector<float> depth = stepEdge(cam, 1.5f, 3.0f, edge, 2.2f);
  for (int which = 0; which < 2; ++which) {  // the jump-edge filter alone, then the confidence filter alone
    DepthFilterConfig c = rejectOnly();
    (which == 0 ? c.confidence.enabled : c.jump_edge.enabled) = false;
    const DepthFilter f(cam, Pose(), c);
    DepthFilterResult r;
    f.apply(view(cam, depth), r);
    for (int v = 0; v < cam.height; ++v) {
      EXPECT_FALSE(r.valid[size_t(v) * cam.width + edge]) << "filter " << which << " row " << v;
      // Away from the edge everything stays.
      for (int u : {0, 5, edge - 5, edge + 5, cam.width - 1}) EXPECT_TRUE(r.valid[size_t(v) * cam.width + u]);
    }
    EXPECT_EQ(r.rejected(which == 0 ? DepthReject::kJumpEdge : DepthReject::kConfidence), cam.numBeams() - r.kept());
    EXPECT_GT(r.kept(), cam.numBeams() * 85 / 100);
  }
}

TEST(DepthFilter, JumpEdgesKeepThinStructures) {
  // A one-pixel-wide pole at 1.5 m in front of a wall at 3 m: both its neighbours are farther,
  // so it is no pixel between two surfaces (the classic `any` mode takes it, and the wall's rim).
  const DepthCameraSpec cam = pmdO3D100();
  const int pole = cam.width / 2;
  const std::vector<float> depth = stepEdge(cam, 3.0f, 3.0f, pole, 1.5f);
  DepthFilterConfig c = rejectOnly();
  c.confidence.enabled = false;
  DepthFilterResult between, any;
  DepthFilter(cam, Pose(), c).apply(view(cam, depth), between);
  c.jump_edge.mode = "any";
  DepthFilter(cam, Pose(), c).apply(view(cam, depth), any);
  EXPECT_EQ(between.kept(), cam.numBeams());
  EXPECT_EQ(any.kept(), cam.numBeams() - 3 * size_t(cam.height));
}

TEST(DepthFilter, ConfidenceRejectsIsolatedOutliersAndKeepsASmoothSurface) {
  const DepthCameraSpec cam = pmdO3D100();
  const Pose mount = Pose::fromXYZRPY(0, 0, 0.75, 0, 0, deg2rad(30));  // a wall seen obliquely
  const CounterRng rng(7);
  std::vector<uint8_t> outlier(cam.numBeams(), 0);
  const std::vector<float> depth = test::depthImage(cam, mount, [&](int u, int v, const Eigen::Vector3d& ray) {
    const size_t i = size_t(v) * cam.width + u;
    float r = float(3.0 / ray.x() + 0.005 * rng.normal(1, i, 0));  // wall x = 3, 5 mm noise
    if (rng.uniform(1, i, 8) < 0.02) outlier[i] = 1, r *= 0.5f;      // reflection-like: half the range
    return r;
  });
  DepthFilterConfig c = rejectOnly();
  c.jump_edge.enabled = false;
  const DepthFilter f(cam, mount, c);
  DepthFilterResult r;
  f.apply(view(cam, depth), r);
  size_t outliers = 0, kept_good = 0, good = 0;
  for (size_t i = 0; i < cam.numBeams(); ++i) {
    if (outlier[i]) {
      ++outliers;
      EXPECT_FALSE(r.valid[i]) << "outlier pixel " << i;
    } else {
      ++good, kept_good += r.valid[i];
    }
  }
  EXPECT_GT(outliers, 30u);
  EXPECT_GT(double(kept_good) / double(good), 0.99);
}

TEST(DepthFilter, RgbEdgesKeepTheConfidenceOfDepthEdges) {
  // Eq. 6.4: across a colour edge the depth difference is not held against a pixel.
  const DepthCameraSpec cam = pmdO3D100();
  const std::vector<float> depth = stepEdge(cam, 1.5f, 1.8f, -1, 0.f);
  std::vector<uint8_t> rgb(cam.numBeams() * 3);
  for (size_t i = 0; i < cam.numBeams(); ++i)
    for (int k = 0; k < 3; ++k) rgb[i * 3 + k] = int(i % cam.width) < cam.width / 2 ? 20 : 230;
  DepthFilterConfig c = rejectOnly();
  c.jump_edge.enabled = false;
  c.confidence.threshold = 0.6;  // strict enough that the edge columns fall without colour
  c.confidence.sigma_c = 0.05;   // and a colour step of this contrast weighs the depth step ~0
  const DepthFilter f(cam, Pose(), c);
  DepthFilterResult plain, coloured;
  f.apply(view(cam, depth), plain);
  f.apply(view(cam, depth, nullptr, &rgb), coloured);
  EXPECT_LT(plain.kept(), cam.numBeams());
  EXPECT_EQ(coloured.kept(), cam.numBeams());
}

TEST(DepthFilter, MedianSmoothingReducesNoiseAndFillsNoHoles) {
  const DepthCameraSpec cam = pmdO3D100();
  const CounterRng rng(3);
  std::vector<float> depth(cam.numBeams());
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = 2.f + 0.005f * float(rng.normal(2, i, 0));
  depth[500] = std::numeric_limits<float>::quiet_NaN();
  for (const char* method : {"median", "bilateral"}) {
    DepthFilterConfig c;
    c.smoothing.method = method;
    c.smoothing.size = 5;
    const DepthFilter f(cam, Pose(), c);
    DepthFilterResult r;
    f.apply(view(cam, depth), r);
    EXPECT_TRUE(std::isnan(r.depth[500])) << method;
    double raw = 0, smooth = 0;
    size_t n = 0;
    for (size_t i = 0; i < depth.size(); ++i)
      if (r.valid[i]) raw += std::pow(depth[i] - 2.0, 2), smooth += std::pow(r.depth[i] - 2.0, 2), ++n;
    EXPECT_LT(std::sqrt(smooth / n), 0.6 * std::sqrt(raw / n)) << method;
  }
}

}  // namespace polyloc::t_depth_filter
