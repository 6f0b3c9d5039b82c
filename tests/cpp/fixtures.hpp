// Analytic test geometry.
#pragma once

#include <polyloc/mapgen/builder.hpp>

namespace polyloc::test {

// Room with interior [-hx, hx] x [-hy, hy] x [0, h] enclosed by solid slabs of thickness t:
// floor, ceiling, four walls that end exactly at the corners, and corner posts, so that a ray
// into a corner meets the edges of three solids at once.
inline Mesh boxRoom(float hx, float hy, float h, float t) {
  Mesh m;
  mapgen::MeshBuilder b(m);
  b.box({-hx - t, -hy - t, -t}, {hx + t, hy + t, 0}, "floor");
  b.box({-hx - t, -hy - t, h}, {hx + t, hy + t, h + t}, "ceiling");
  b.box({hx, -hy, 0}, {hx + t, hy, h}, "wall");
  b.box({-hx - t, -hy, 0}, {-hx, hy, h}, "wall");
  b.box({-hx, hy, 0}, {hx, hy + t, h}, "wall");
  b.box({-hx, -hy - t, 0}, {hx, -hy, h}, "wall");
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const Eigen::Vector3f c(sx * (hx + t / 2), sy * (hy + t / 2), 0);
      b.box(c + Eigen::Vector3f(-t / 2, -t / 2, 0), c + Eigen::Vector3f(t / 2, t / 2, h), "wall");
    }
  return m;
}

}  // namespace polyloc::test
