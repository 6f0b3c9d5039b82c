// The picture of a simulated run (`polyloc simulate --plot`): the map slice, the ground-truth
// path, the people's paths, and one frame of every sensor (scanner end points, ToF points
// projected to the floor), the robot and the people at that moment.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace polyloc::viz {

struct SimPlotData {
  std::vector<Eigen::Vector2f> truth_path;                 // robot, map frame
  std::vector<std::vector<Eigen::Vector2f>> people_paths;  // per person
  struct SensorFrame {
    std::string name;
    Pose map_T_sensor;
    std::vector<Eigen::Vector3f> points;  // end points, map frame
    bool depth_camera = false;
  };
  std::vector<SensorFrame> frames;              // one per sensor, at plot_time
  double plot_time = 0;                         // s
  Pose robot;                                   // at plot_time
  std::vector<Eigen::Vector2f> robot_outline;   // footprint, map frame
  std::vector<Eigen::Vector2f> people_now;      // positions at plot_time
  std::string title;
};

// Throws std::runtime_error naming the file when it cannot be written.
void drawSimulation(const Mesh& map, const SimPlotData& data, const std::string& png_path);

}  // namespace polyloc::viz
