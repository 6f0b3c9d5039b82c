// The robot's body as localisation, simulation and obstacle avoidance need it: footprint,
// height, kinematics. YAML (section `robot:` of a polyloc configuration):
//
//   robot:
//     footprint: [[0.3, 0.25], [-0.3, 0.25], [-0.3, -0.25], [0.3, -0.25]]  # polygon, base frame, m
//     # or: radius: 0.25                                                    # round footprint
//     height: 1.2               # m
//     kinematics: differential  # or omni
#pragma once

#include <polyloc/config/yaml.hpp>

#include <Eigen/Core>
#include <vector>

namespace polyloc {

enum class Kinematics { Differential, Omni };

struct RobotSpec {
  std::vector<Eigen::Vector2d> footprint;  // simple polygon in base_link x/y; empty: round
  double radius = 0.25;                    // m, used when footprint is empty
  double height = 1.0;                     // m above the floor
  Kinematics kinematics = Kinematics::Differential;

  double boundingRadius() const;  // largest distance of the outline from base_link
  // Smallest distance of the outline from base_link: the circle about base_link that the body
  // surely covers (0 when base_link lies outside the footprint).
  double inscribedRadius() const;
  // Points on the outline, at most `spacing` apart (base frame).
  std::vector<Eigen::Vector2d> outline(double spacing) const;
  // Where the robot touches the floor: the footprint's corners (a polygon), or four points at
  // 0.8 of the radius (round). The simulator fits the floor plane through these.
  std::vector<Eigen::Vector2d> contactPoints() const;
};

RobotSpec parseRobot(ConfigMap m);  // throws ConfigError
const char* kinematicsName(Kinematics k);

}  // namespace polyloc
