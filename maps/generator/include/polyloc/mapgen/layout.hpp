// Where a generator put things: the facts that tests and simulations need without searching the
// mesh (door openings, tables, chairs, the ramp, the stairwell). Map frame, metres.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace polyloc {

struct DoorInfo {
  std::string name;         // "lab 1", "room r0c2", "loading bay"
  Eigen::Vector2f centre;   // on the wall's centre line, at floor level
  Eigen::Vector2f along;    // unit vector along the wall
  float width = 0, height = 0;  // clear opening
  float floor_z = 0;        // height of the floor at the opening
  bool closed = false;      // a door leaf fills the opening (otherwise it stands open)
};

struct MapLayout {
  Eigen::AlignedBox2f building;                 // outer wall centre lines
  std::vector<DoorInfo> doors;
  std::vector<Eigen::Vector2f> tables;          // table top centres
  std::vector<Eigen::Vector2f> chairs;          // seat centres
  std::vector<Eigen::AlignedBox2f> ramps;       // footprints of ramps
  std::vector<Eigen::AlignedBox2f> platforms;   // raised floor areas
  std::vector<Eigen::AlignedBox2f> stairwells;  // openings in the floor with stairs going down
};

}  // namespace polyloc
