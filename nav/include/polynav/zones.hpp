// Navigation zones: the regions where the controller behaves differently. Door regions (align in
// front of the door, pass centred and slow), goal spots (approach through an intermediate pose, dock
// within 2 cm), corridors (drive parallel to the axis, correct drift), danger zones (never planned
// through, never entered), rooms (named in status messages). Curve regions are not zones: the
// orientation there comes from the path.
//
// Geometry is in the map frame (x, y in metres, yaw in radians counter-clockwise from +x). Polygons
// are simple (no self-crossing), possibly non-convex, either winding, the last point joined to the
// first. Point-in-polygon is by winding number; a point on a polygon's boundary counts as inside
// (where two rooms share a wall, the first in the list wins). Every query is deterministic.
//
// Zone file (YAML, loadZones), every section optional, every key checked:
//
//   rooms:      # named areas, for status messages
//     - {name: lab 1, polygon: [[0, 3.5], [6.5, 3.5], [6.5, 14], [0, 14]]}
//   doors:      # centre on the wall's centre line, `along` along the wall (normalised on load)
//     - {name: lab 1, centre: [5.0, 3.5], along: [1, 0], width: 0.75}
//       # optional: depth: 0.6    the door region reaches this far on each side of the wall (m)
//       #           wall: 0.15    thickness of the wall: the opening markDoors labels (m)
//       #           closed: false a closed door has no region and no passage; markDoors makes
//       #                         its opening an obstacle
//   corridors:  # drive parallel to `axis` (normalised on load; its sign does not matter)
//     - {name: corridor, polygon: [[0, 0], [19.5, 0], [19.5, 3.5], [0, 3.5]], axis: [1, 0]}
//   danger:     # never entered by any part of the footprint, never planned through
//     - {name: stairwell, polygon: [[23.45, 3.55], [26.05, 3.55], [26.05, 10.13], [23.45, 10.13]]}
//   goals:      # pose [x, y, yaw]: yaw in degrees, or with a unit: "1.57 rad", "90 deg"
//     - {name: lab 1 bench, pose: [1.40, 7.825, 180]}
//       # optional: approach: 0.5   the intermediate pose lies this far behind the goal along
//       #                           its heading (m, >= 0; 0: no intermediate pose)
//
// Errors (ZonesError) name the file, the line and column, and the key: YAML syntax, a missing
// key, an unknown or repeated key (typos never pass silently), a value of the wrong kind, a number
// that is not finite (.nan, .inf), a point that is not two numbers, a polygon with fewer than
// 3 points or one that is not simple or has no area, a door width or depth <= 0 or a wall < 0, a
// zero `along` or corridor `axis`, an approach outside [0, 10] m, a name that is empty or given twice in one
// section (a room and a door may share a name), a goal or its approach pose inside a danger zone,
// a goal more than 10 m outside the rooms and corridors.
#pragma once

#include <polynav/nav_grid.hpp>
#include <polynav/polygon.hpp>  // Polygon and the polygon tools, for every user of zones.hpp

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace polynav {

struct Door {
  std::string name;
  Eigen::Vector2d centre{0, 0};  // on the wall's centre line
  Eigen::Vector2d along{1, 0};   // unit, along the wall
  double width = 0;              // clear opening, m
  double depth = 0.6;            // the door region extends this far on each side of the wall, m
  double wall = 0.15;            // thickness of the wall the door is in, m (the opening's depth)
  bool closed = false;           // a leaf fills the opening: no region, no passage, an obstacle

  // `along` turned by +90 degrees: the wall's normal, towards the door's left side.
  Eigen::Vector2d normal() const { return {-along.y(), along.x()}; }
  // The door region: centre +- width/2 along, +- depth across (closed interval). False for a
  // closed door and for a point that is not finite.
  bool contains(const Eigen::Vector2d& p) const;
};

struct Room {
  std::string name;
  Polygon polygon;
};

struct Corridor {
  std::string name;
  Polygon polygon;
  Eigen::Vector2d axis{1, 0};  // unit; the direction to drive parallel to (either sign)
};

struct DangerZone {
  std::string name;
  Polygon polygon;
};

struct GoalSpot {
  std::string name;
  Eigen::Vector3d pose{0, 0, 0};  // x, y, yaw (rad)
  double approach = 0.5;          // m: the intermediate pose lies this far behind the goal along its heading
};

// The two poses of a door passage, in travel order: `before` on the side the robot comes from,
// `after` on the other, both on the door's centre line at `depth` from the wall, facing through.
struct DoorPassage {
  Eigen::Vector3d before{0, 0, 0}, after{0, 0, 0};  // x, y, yaw
};

class ZonesError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Zones {
  std::vector<Room> rooms;
  std::vector<Door> doors;
  std::vector<Corridor> corridors;
  std::vector<DangerZone> danger;
  std::vector<GoalSpot> goals;

  // Name of the first room containing p, "" for none (or p not finite).
  std::string roomAt(const Eigen::Vector2d& p) const;
  // Index of the first open door whose region contains p; none for none (or p not finite).
  std::optional<size_t> doorAt(const Eigen::Vector2d& p) const;
  // Index of the first corridor containing p; none for none (or p not finite).
  std::optional<size_t> corridorAt(const Eigen::Vector2d& p) const;
  // Whether p lies in (or on the boundary of) a danger zone.
  // Throws std::invalid_argument for p not finite: "not in danger" would be a wrong answer.
  bool inDanger(const Eigen::Vector2d& p) const;
  // Whether the footprint (a polygon in base_link x/y, at least 3 points) placed at pose (x, y, yaw)
  // overlaps any danger zone: polygon-polygon intersection, touching counts. Throws
  // std::invalid_argument for a footprint of < 3 points or anything not finite.
  bool inDanger(const Polygon& footprint, const Eigen::Vector3d& pose) const;
  // Distance (m) from p to the nearest danger zone: 0 inside, +inf without danger zones. Throws
  // std::invalid_argument for p not finite.
  double dangerDistance(const Eigen::Vector2d& p) const;
  // Index of the entry with that name; none if there is none.
  std::optional<size_t> doorIndex(const std::string& name) const;
  std::optional<size_t> goalIndex(const std::string& name) const;

  // The checks of loadZones (those without a file position) on zones built in code: throws
  // std::invalid_argument naming the entry ("doors[1] 'lab 2': width must be > 0, got 0").
  // The query functions do not call it.
  void validate() const;
};

// Throws std::invalid_argument for a closed door, a door that is not valid or `from_side_point`
// not finite. A point on the wall's line counts as on the normal's side.
DoorPassage doorPassage(const Door& door, const Eigen::Vector2d& from_side_point);

// The intermediate pose: `approach` behind the goal along its heading, with the goal's yaw.
Eigen::Vector3d approachPose(const GoalSpot& goal);

// `n` goals drawn at random from zones.goals (mt19937_64 seeded with `seed`), never the same one
// twice in a row: random missions (polynav --random, polyloc eval nav). Throws ZonesError for
// fewer than 2 goals.
std::vector<GoalSpot> randomGoals(const Zones& zones, size_t n, uint64_t seed);

// Reads a zone file (format above); the result passes Zones::validate. Throws ZonesError.
Zones loadZones(const std::string& yaml_path);

// Sets occupied = 1 in the cells of `g` whose centre lies inside or within half a cell of a danger
// polygon, so that a planner never plans through them (inflating afterwards keeps the footprint out).
// Throws std::invalid_argument for a bad grid (NavGrid::validate).
void markDanger(const Zones& zones, NavGrid& g);
// Door openings: the cells whose centre lies inside or within half a cell of a door's opening
// (centre +- width/2 along, +- wall/2 across). Open doors set NavGrid::door = 1 there (allocating
// `door` as zeros when empty); closed doors set occupied = 1 instead. Throws std::invalid_argument
// for a bad grid.
void markDoors(const Zones& zones, NavGrid& g);

}  // namespace polynav
