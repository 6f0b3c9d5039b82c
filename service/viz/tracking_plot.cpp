#include "viz/tracking_plot.hpp"

#include "viz/topview.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace polyloc::viz {

void drawTracking(const Mesh& map, const TrackingPlotData& d, const std::string& png_path) {
  const Eigen::AlignedBox3f box = map.bounds();
  Eigen::AlignedBox2f area(box.min().head<2>(), box.max().head<2>());
  const int lines = 3 + static_cast<int>(std::count(d.legend.begin(), d.legend.end(), '\n'));
  area.max().y() += 0.45f * static_cast<float>(lines);  // room for the legend (18 px a line)
  TopView view(area, 40.f);
  const Color light{200, 200, 200};
  view.drawMeshSlice(map, 0.74f, &light, 1);
  view.drawMeshSlice(map, d.slice_height, nullptr, 2);
  for (size_t i = 1; i < d.robot_path.size(); ++i) view.drawLine(d.robot_path[i - 1], d.robot_path[i], kBlue, 2);
  const Color care{150, 60, 170}, ignored{190, 190, 190};
  for (const auto& path : d.people)
    for (size_t i = 1; i < path.size(); ++i) {
      if ((path[i].p - path[i - 1].p).norm() > 0.5f) continue;
      view.drawLine(path[i - 1].p, path[i].p, path[i].care ? care : ignored, 3);
    }
  const Color palette[] = {kRed, kGreen, kOrange, kCyan, {200, 40, 160}, {120, 80, 20}, {20, 120, 120}, {90, 90, 220}};
  for (const auto& t : d.tracks) {
    const Color c = palette[t.id % std::size(palette)];
    for (size_t i = 1; i < t.points.size(); ++i) view.drawLine(t.points[i - 1], t.points[i], c, 1);
    if (!t.points.empty()) {
      view.drawPoint(t.points.front(), c, 3);
      view.drawText(fmt::format("{}", t.id), t.points.front() + Eigen::Vector2f(0.1f, 0.1f), c);
    }
  }
  std::string legend = d.title;
  if (!d.legend.empty()) legend += "\n" + d.legend;
  legend += "\nblue: robot; purple: people walking in view (grey: hidden, far or standing); colours: tracks";
  view.drawLegend(legend);
  view.drawScaleBar();
  view.save(png_path);
}

}  // namespace polyloc::viz
