#include "viz/topview.hpp"

#include <polyloc/map/slice.hpp>

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <filesystem>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_viz {

using namespace polyloc;

TEST(Slice, BoxRoomSliceIsItsWalls) {
  const Mesh room = test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  const auto segs = sliceMesh(room, 1.0f);
  // 4 walls + 4 posts, 4 sides each, 2 triangles per side => 2 segments per side.
  EXPECT_EQ(segs.size(), 8u * 4u * 2u);
  double inner_x = 0;
  for (const auto& s : segs)
    if (std::abs(s.a.x() - 2.f) < 1e-6 && std::abs(s.b.x() - 2.f) < 1e-6) inner_x += std::abs(s.a.y() - s.b.y());
  // x = 2: the wall face (y in [-1.5, 1.5]) plus the faces of two posts and two wall ends (0.2 each).
  EXPECT_NEAR(inner_x, 3.8, 1e-5);
  EXPECT_TRUE(sliceMesh(room, 10.f).empty());
}

TEST(TopView, WritesPngAndReportsBadPath) {
  const Mesh room = test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  viz::TopView view(Eigen::AlignedBox2f(Eigen::Vector2f(-2.5f, -2.f), Eigen::Vector2f(2.5f, 2.f)), 50.f, 10);
  EXPECT_EQ(view.width(), 270);
  EXPECT_EQ(view.height(), 220);
  view.drawMeshSlice(room, 1.f);
  view.drawPose(Pose::planar(0, 0, 0.5), viz::kRed);
  const auto png = std::filesystem::temp_directory_path() / "polyloc_topview_test.png";
  view.save(png.string());
  EXPECT_GT(std::filesystem::file_size(png), 500u);
  std::filesystem::remove(png);
  try {
    view.save("/nonexistent-dir/x.png");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos);
  }
}

}  // namespace polyloc::t_viz
