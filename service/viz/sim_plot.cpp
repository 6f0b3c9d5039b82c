#include "viz/sim_plot.hpp"

#include "viz/topview.hpp"

#include <fmt/core.h>

namespace polyloc::viz {

void drawSimulation(const Mesh& map, const SimPlotData& d, const std::string& png_path) {
  const Eigen::AlignedBox3f box = map.bounds();
  // Room above the map for the legend: a line of text is 18 px, 0.45 m at 40 px/m.
  const int lines = 3 + static_cast<int>(d.frames.size() + 2) / 3;
  Eigen::AlignedBox2f area(box.min().head<2>(), box.max().head<2>());
  area.max().y() += 0.45f * lines;
  TopView view(area, 40.f);
  const Color light{200, 200, 200};
  view.drawMeshSlice(map, 0.74f, &light, 1);  // table tops and shelves, for orientation
  view.drawMeshSlice(map, 0.2f, nullptr, 2);
  const Color people_color{150, 60, 170};
  for (const auto& path : d.people_paths)
    for (size_t i = 1; i < path.size(); ++i) view.drawLine(path[i - 1], path[i], people_color, 1);
  for (size_t i = 1; i < d.truth_path.size(); ++i) view.drawLine(d.truth_path[i - 1], d.truth_path[i], kBlue, 2);
  const Color palette[] = {kRed, kGreen, kOrange, kCyan, {200, 40, 160}, {120, 80, 20}, {20, 120, 120}, {90, 90, 220}};
  std::string legend = d.title + fmt::format("\nblue: ground truth; purple: people; sensors at t = {:.1f} s:", d.plot_time);
  for (size_t s = 0; s < d.frames.size(); ++s) {
    const auto& f = d.frames[s];
    const Color c = palette[s % std::size(palette)];
    const int r = f.depth_camera ? 1 : 2;
    for (const Eigen::Vector3f& p : f.points) view.drawPoint(p.head<2>(), c, r);
    legend += fmt::format("{} {} ({} pts)", s % 3 == 0 ? "\n " : ",", f.name, f.points.size());
  }
  for (size_t i = 0; i < d.robot_outline.size(); ++i)
    view.drawLine(d.robot_outline[i], d.robot_outline[(i + 1) % d.robot_outline.size()], kBlack, 2);
  view.drawPose(d.robot, kBlack, 0.2f);
  for (const auto& p : d.people_now) view.drawPose(Pose::planar(p.x(), p.y(), 0), people_color, 0.25f);
  view.drawLegend(legend);
  view.drawScaleBar();
  view.save(png_path);
}

}  // namespace polyloc::viz
