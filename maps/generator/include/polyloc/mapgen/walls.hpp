// Floor plans of straight, axis-aligned walls given by their centre lines, with door openings.
// A wall with openings becomes boxes: the pieces beside each opening and a lintel above it that
// reaches a little into the pieces. Collinear walls that touch are merged, and at corners only
// the wall along x is lengthened by half a thickness, so that no two wall boxes share a vertex
// position (see builder.hpp for why).
#pragma once

#include <polyloc/mapgen/builder.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace polyloc::mapgen {

struct WallStyle {
  float thickness = 0.15f;      // m
  float height = 2.8f;          // top of the walls above z0
  float z0 = 0.f;               // bottom of the walls (the floor top)
  float lintel_overlap = 0.05f;  // how far a lintel reaches into the wall beside the opening
  std::string label = "wall";
};

class WallPlan {
 public:
  explicit WallPlan(WallStyle style = {}) : style_(std::move(style)) {}
  const WallStyle& style() const { return style_; }

  // A wall along the centre line a-b; a and b share x or y.
  void addWall(const Eigen::Vector2f& a, const Eigen::Vector2f& b);
  // A line that walls may end on but that this plan does not build (a glass facade built
  // separately): walls ending there are treated as meeting a wall at a corner or T.
  void addGuide(const Eigen::Vector2f& a, const Eigen::Vector2f& b);
  // An opening of the given clear width, from the wall bottom up to height, centred at a point on
  // a wall's centre line. Checked in build(): throws std::invalid_argument if no wall holds it.
  void addOpening(const Eigen::Vector2f& centre, float width, float height);

  void build(MeshBuilder& builder) const;

 private:
  struct Line {
    bool along_x;    // the wall runs along x (at y = coord) or along y (at x = coord)
    float coord;     // y for walls along x, x for walls along y
    float lo, hi;    // extent along the wall
    bool solid;      // false for guides
  };
  struct Opening {
    Eigen::Vector2f centre;
    float width, height;
  };
  std::vector<Line> merged() const;
  float extension(const Line& wall, float end, const std::vector<Line>& all) const;

  WallStyle style_;
  std::vector<Line> lines_;
  std::vector<Opening> openings_;
};

}  // namespace polyloc::mapgen
