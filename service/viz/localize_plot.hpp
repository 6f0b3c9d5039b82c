// The picture of a localisation run (`polyloc localize --plot`): the map slice, the ground-truth
// path, the estimated path, particle clouds (a subsample) at a few instants with the estimate
// there, and a legend with the metrics.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace polyloc::viz {

struct LocalizePlotData {
  std::vector<Eigen::Vector2f> truth_path;     // map frame
  std::vector<Eigen::Vector2f> estimate_path;  // map frame, one point per update
  struct Cloud {
    double t_s = 0;                         // since the start of the run
    uint64_t update = 0;
    Pose estimate;
    std::vector<Eigen::Vector2f> particles;  // x, y of a subsample
  };
  std::vector<Cloud> clouds;
  std::string title;
  std::string legend;  // lines of metrics, below the title
  float slice_height = 0.2f;  // m above the floor: what a low scanner sees
};

// Throws std::runtime_error naming the file when it cannot be written.
void drawLocalization(const Mesh& map, const LocalizePlotData& data, const std::string& png_path);

}  // namespace polyloc::viz
