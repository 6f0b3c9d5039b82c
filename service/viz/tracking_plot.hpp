// The picture of a tracking evaluation (`polyloc eval tracking --plot`): the map slice at the
// scanners' height, the robot's path, the people's true paths (grey where they do not count:
// hidden, far or standing), each confirmed track's path in its own colour with its id at the
// start, and a legend with the metrics.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace polyloc::viz {

struct TrackingPlotData {
  std::vector<Eigen::Vector2f> robot_path;
  struct TruthPoint {
    Eigen::Vector2f p;
    bool care = true;
  };
  std::vector<std::vector<TruthPoint>> people;  // per person, in time order (breaks: gaps > 0.5 m)
  struct TrackPath {
    uint32_t id = 0;
    std::vector<Eigen::Vector2f> points;
  };
  std::vector<TrackPath> tracks;
  std::string title, legend;
  float slice_height = 0.1f;
};

// Throws std::runtime_error naming the file when it cannot be written.
void drawTracking(const Mesh& map, const TrackingPlotData& data, const std::string& png_path);

}  // namespace polyloc::viz
