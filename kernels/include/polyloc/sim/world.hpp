// The world the simulated sensors see, when it is not the localisation map: a building differs
// from its plan. The localiser weighs against the map; the simulator casts into this world, so
// a run can test the localiser on a model that is wrong the way real maps are wrong: furniture
// removed or added, walls a few centimetres off, another tessellation of the same surfaces, and
// clutter the map lacks. Chair moves (chairs.hpp) are applied first, then these, in this order:
// own mesh, remove, add, wall offsets, clutter, subdivision.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace polyloc {

struct WorldRemove {
  std::string label;              // the object of this label whose centre is nearest `at`,
  Eigen::Vector2d at{0, 0};       // within 0.6 m, is removed
  std::string where;              // "file:line", for errors
};

struct WorldBox {
  Eigen::Vector3d lo{0, 0, 0}, hi{0, 0, 0};  // corners before the turn
  double yaw = 0;                             // rad, about the box's vertical centre line
  std::string label = "clutter";
};

struct ClutterSpec {
  int count = 0;                    // boxes on free floor, away from the route
  double size_min = 0.15, size_max = 0.6;    // m, side lengths (x and y drawn apart)
  double height_min = 0.1, height_max = 1.0; // m
  double route_clearance = 0.8;     // m from the robot's path (its centre line)
  std::string label = "clutter";
};

struct WorldSpec {
  std::string mesh;                 // a mesh file of its own (resolved path); "" = the map
  std::vector<WorldRemove> remove;
  std::vector<WorldBox> add;
  double wall_offset = 0;           // m: each solid of an offset label shifts by up to this
  std::vector<std::string> offset_labels{"wall"};
  ClutterSpec clutter;
  int subdivide = 0;                // times every triangle is split in four (0..3)
  std::optional<uint64_t> seed;     // default: the scenario's seed
  bool empty() const {
    return mesh.empty() && remove.empty() && add.empty() && wall_offset <= 0 && clutter.count <= 0 && subdivide <= 0;
  }
};

// What buildWorld changed, for the simulator's summary.
struct WorldChanges {
  size_t removed = 0, added = 0, shifted = 0, clutter = 0;
  size_t triangles_before = 0, triangles_after = 0;
};

// `base`: the map (or the world's own mesh) with chairs moved; `route`: points of the robot's
// path (clutter keeps clear of it). Throws std::runtime_error naming the entry ("file:line")
// when a removal finds no object, or when clutter cannot be placed (no free floor).
Mesh buildWorld(const Mesh& base, const WorldSpec& spec, uint64_t seed,
                const std::vector<Eigen::Vector2d>& route, WorldChanges* changes = nullptr);

}  // namespace polyloc
