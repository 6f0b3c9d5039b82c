// Bresenham's line over grid cells, shared by the obstacle memory and the danger zones (both
// read their grids back along each VRS segment's ray) and map/scan_mapper (each beam's cells).
#pragma once

#include <cstdint>
#include <cstdlib>

namespace polyloc {

// Visits the cells from (x0, y0) to (x1, y1), both included, until visit(x, y) returns true.
// Returns whether it stopped early.
template <class Visit>
bool walkCells(int32_t x0, int32_t y0, int32_t x1, int32_t y1, Visit&& visit) {
  const int32_t dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int32_t sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int32_t err = dx + dy;
  for (;;) {
    if (visit(x0, y0)) return true;
    if (x0 == x1 && y0 == y1) return false;
    const int32_t e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

}  // namespace polyloc
