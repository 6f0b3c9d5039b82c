// Chairs moved between runs: the map stays as built, the chairs in it do not. A chair is found
// as the triangles of one label ("chair") that hang together (shared vertices, or touching
// bounding boxes: a chair is several solids that overlap). Moves are explicit (from a position
// to another, with a turn) or seed-driven (every chair shifted and turned by a random amount).
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace polyloc {

struct ChairMove {
  Eigen::Vector2d from{0, 0};  // a chair's centre within 0.6 m of this is moved
  Eigen::Vector2d to{0, 0};    // its new centre
  double rotate = 0;           // rad, turn about its centre
  std::string where;           // "file:line" of the move, for errors
};

struct ChairMoves {
  std::string label = "chair";
  std::vector<ChairMove> moves;
  double random_shift = 0;     // m: each chair moves by up to this (uniform in a disc)
  double random_rotation = 0;  // rad: and turns by up to +- this
  std::optional<uint64_t> seed;  // for the random moves; default: the scenario's seed
  bool empty() const { return moves.empty() && random_shift <= 0 && random_rotation <= 0; }
};

struct MeshObject {
  std::vector<uint32_t> triangles;
  Eigen::AlignedBox3f bounds;
  Eigen::Vector2d centre() const {
    const Eigen::Vector3f c = bounds.center();
    return {c.x(), c.y()};
  }
};

// The objects made of triangles with this label: solids (triangles sharing vertices), joined
// into one object when their bounding boxes touch unless `join_touching` is false.
std::vector<MeshObject> findObjects(const Mesh& mesh, const std::string& label, bool join_touching = true);

// The mesh with the chairs moved (explicit moves first, then random ones to every chair).
// Throws std::runtime_error naming the move's position in the scenario when no chair is near
// its `from`. `moved` receives (old centre, new centre) per chair moved.
Mesh moveChairs(const Mesh& mesh, const ChairMoves& spec, uint64_t seed,
                std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>* moved = nullptr);

}  // namespace polyloc
