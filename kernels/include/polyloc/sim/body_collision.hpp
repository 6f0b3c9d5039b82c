// The robot's body in 3D against the world mesh and people: the footprint extruded from just above
// the floor (floor_clearance) to the robot's height, at a planar pose, tested exactly (separating
// axes, convex_overlap.hpp) against mesh triangles found through a 2D grid and against the
// people's boxes. It catches what a 2D scanner misses: table tops, chair seats, overhangs.
#pragma once

#include <polyloc/config/robot.hpp>
#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/sim/people.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

inline constexpr uint32_t kNoBodyTriangle = 0xFFFFFFFFu;  // same value as raycast's kNoHit

struct BodyContact {
  bool hit = false;
  std::string what;                     // "map" or "person"; "" without contact
  uint32_t triangle = kNoBodyTriangle;  // the mesh triangle touched ("map")
  std::string label;                    // the triangle's label name ("" unlabelled), or "person <index>"
  // A point of the contact (map frame), inside or on the body's bounding box: the centroid of the
  // triangle's vertices inside the body, else the point of the triangle (or the person's box)
  // nearest the body's centre, clamped to that box.
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
};

class BodyCollider {
 public:
  // Keeps a copy of `world` (the caller's mesh may go). The body is body.footprint (a simple polygon, either
  // winding), or a regular 16-gon of body.radius when empty, from floor_clearance (the floor
  // the robot stands on is no collision) to body.height. Throws std::invalid_argument for a
  // footprint without area or not simple, or a floor_clearance outside [0, height).
  BodyCollider(const Mesh& world, const RobotSpec& body, double floor_clearance = 0.02);

  // The first contact of the body placed at map_T_base (its x, y, z and yaw; roll and pitch are
  // ignored: the base stands upright): the mesh first (lowest overlapping triangle index), then
  // the people in scene order. Touching counts as contact. Throws std::invalid_argument naming
  // the value for a non-finite pose or one beyond 1e6 m: callers check their inputs.
  BodyContact check(const Pose& map_T_base, const PeopleScene* people = nullptr) const;

  // The footprint as convex pieces (base frame, counter-clockwise), each extruded separately.
  const std::vector<std::vector<Eigen::Vector2d>>& pieces() const { return pieces_; }

 private:
  struct Entry {  // one triangle in one grid cell, with its z range for a quick height reject
    uint32_t tri;
    float zmin, zmax;
  };
  Eigen::Vector3d vertex(uint32_t tri, int k) const { return mesh_.vertices[mesh_.triangles[tri][k]].cast<double>(); }
  std::array<long, 4> cellRange(const Eigen::AlignedBox3d& b) const;  // i0, i1, j0, j1 clamped to the grid

  Mesh mesh_;
  std::vector<std::vector<Eigen::Vector2d>> pieces_;
  double z0_, z1_;  // body bottom and top above the pose's z
  // Broad phase: uniform grid over the mesh's x/y bounds, cells in compressed rows.
  double gx_ = 0, gy_ = 0, cell_ = 0.5;
  long nx_ = 0, ny_ = 0;
  std::vector<size_t> cell_start_;  // nx * ny + 1 offsets into entries_
  std::vector<Entry> entries_;
};

}  // namespace polyloc
