// Top-view pictures (PNG) in map coordinates: map slices, rays, points, robot poses, text.
// One canvas per picture; x to the right, y up, as a map is read.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/mesh.hpp>

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>

namespace polyloc::viz {

using Color = std::array<uint8_t, 3>;  // RGB
inline constexpr Color kBlack{0, 0, 0}, kGray{170, 170, 170}, kRed{220, 30, 30},
    kBlue{40, 90, 220}, kGreen{30, 160, 60}, kOrange{240, 140, 20}, kCyan{0, 170, 200};

// Colour for a semantic label (wall black, glass cyan, door brown, danger red, furniture grey-blue).
Color labelColor(const std::string& label);

class TopView {
 public:
  // The canvas covers `bounds` (map x/y, metres) plus a margin, at `px_per_m`.
  TopView(const Eigen::AlignedBox2f& bounds, float px_per_m = 40.f, int margin_px = 30);
  ~TopView();

  // Slice of the mesh at `height`, coloured by label (or `color` for every label when given).
  void drawMeshSlice(const Mesh& mesh, float height, const Color* color = nullptr, int thickness = 2);
  // Cells of an occupancy grid as filled squares: occupied black, free white (the background),
  // unknown light grey (map_server's picture).
  void drawGrid(const OccupancyGrid& grid);
  void drawLine(const Eigen::Vector2f& a, const Eigen::Vector2f& b, Color c, int thickness = 1);
  void drawPoint(const Eigen::Vector2f& p, Color c, int radius_px = 2);
  // Robot as a circle with a heading tick.
  void drawPose(const Pose& pose, Color c, float radius_m = 0.3f);
  void drawText(const std::string& text, const Eigen::Vector2f& at, Color c = kBlack);
  void drawLegend(const std::string& text);  // top-left corner of the picture
  void drawScaleBar();                        // 1 m / 5 m bar in the lower left

  // Throws std::runtime_error naming the file when it cannot be written.
  void save(const std::string& png_path) const;
  int width() const;
  int height() const;

 private:
  struct Canvas;
  std::unique_ptr<Canvas> canvas_;
};

}  // namespace polyloc::viz
