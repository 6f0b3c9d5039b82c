// The bundled map `office`: a grid of offices off corridors, the benchmark map of the ray casters
// (about 10,000 triangles by default). Rows of rooms come in pairs facing a shared corridor
// along x; a cross corridor along the west side joins the corridors. Each room has a door
// opening whose leaf stands open against the wall, tables and chairs.
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/mapgen/layout.hpp>

namespace polyloc {

struct OfficeOptions {
  int rows = 4;                  // rows of rooms along y; rows 2k and 2k+1 share corridor k
  int cols = 6;                  // rooms per row along x
  float room_width = 4.0f;       // along x, wall centre line to centre line
  float room_depth = 5.0f;       // along y
  float corridor_width = 2.0f;   // the corridors between rows and the cross corridor
  float wall_height = 2.8f;
  float wall_thickness = 0.12f;
  float door_width = 0.9f;       // clear opening
  float door_height = 2.0f;
  int tables_per_room = 2;       // desks along the side walls (at most 2)
  int chairs_per_room = 1;       // chairs at the first desks (at most tables_per_room)
  bool shelf = true;             // a low shelf against the back wall
};

// Deterministic. Throws std::invalid_argument for options that do not make a building.
Mesh generateOffice(const OfficeOptions& options = {}, MapLayout* layout = nullptr);

}  // namespace polyloc
