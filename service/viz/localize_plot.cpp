#include "viz/localize_plot.hpp"

#include "viz/topview.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace polyloc::viz {

void drawLocalization(const Mesh& map, const LocalizePlotData& d, const std::string& png_path) {
  const Eigen::AlignedBox3f box = map.bounds();
  Eigen::AlignedBox2f area(box.min().head<2>(), box.max().head<2>());
  // Paths or particles off the map (a lost filter) still belong in the picture.
  for (const auto& p : d.truth_path) area.extend(p);
  for (const auto& p : d.estimate_path) area.extend(p);
  // Room above the map for the legend: a line of text is 18 px, 0.45 m at 40 px/m.
  const int lines = 3 + static_cast<int>(std::count(d.legend.begin(), d.legend.end(), '\n')) +
                    static_cast<int>(d.clouds.size() + 1) / 2;
  area.max().y() += 0.45f * static_cast<float>(lines);
  // Large maps at 40 px/m give huge pictures: keep the long side near 4000 px.
  const float extent = std::max(area.sizes().x(), area.sizes().y());
  const float px_per_m = std::clamp(4000.f / std::max(extent, 1.f), 10.f, 40.f);
  TopView view(area, px_per_m);
  const Color light{200, 200, 200};
  view.drawMeshSlice(map, 0.74f, &light, 1);  // table tops and shelves, for orientation
  view.drawMeshSlice(map, d.slice_height, nullptr, 2);

  const Color palette[] = {kOrange, {200, 40, 160}, kCyan, {120, 80, 20}, kGreen, {90, 90, 220}};
  std::string legend = d.title;
  if (!d.legend.empty()) legend += "\n" + d.legend;
  legend += d.clouds.empty() ? "\nblue: ground truth; red: estimate" : "\nblue: ground truth; red: estimate; particle clouds:";
  for (size_t c = 0; c < d.clouds.size(); ++c) {
    const auto& cloud = d.clouds[c];
    legend += fmt::format("{} t = {:.1f} s (update {}, {} shown)", c % 2 == 0 ? "\n " : ";", cloud.t_s,
                          cloud.update, cloud.particles.size());
  }
  for (size_t i = 1; i < d.truth_path.size(); ++i) view.drawLine(d.truth_path[i - 1], d.truth_path[i], kBlue, 2);
  // A jump (a lost filter) is a new start, not a line across the map.
  for (size_t i = 1; i < d.estimate_path.size(); ++i) {
    if ((d.estimate_path[i] - d.estimate_path[i - 1]).norm() < 0.5f) view.drawLine(d.estimate_path[i - 1], d.estimate_path[i], kRed, 1);
    else view.drawPoint(d.estimate_path[i], kRed, 1);
  }
  for (size_t c = 0; c < d.clouds.size(); ++c) {
    const auto& cloud = d.clouds[c];
    view.drawPose(cloud.estimate, palette[c % std::size(palette)], 0.25f);
    const Eigen::Vector2f at(static_cast<float>(cloud.estimate.x()) + 0.3f, static_cast<float>(cloud.estimate.y()) + 0.3f);
    view.drawText(fmt::format("{:.0f} s", cloud.t_s), at);
  }
  // Particles last: in tracking the cloud is smaller than the pose marker.
  for (size_t c = 0; c < d.clouds.size(); ++c)
    for (const auto& p : d.clouds[c].particles) view.drawPoint(p, palette[c % std::size(palette)], 1);
  view.drawLegend(legend);
  view.drawScaleBar();
  view.save(png_path);
}

}  // namespace polyloc::viz
