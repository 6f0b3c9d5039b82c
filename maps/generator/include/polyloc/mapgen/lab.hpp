// The bundled map `lab`: one floor of a life-science lab building, 26 m x 14 m (outer wall centre
// lines, x east, y north, floor top at z = 0, no ceiling). Along the south side a corridor runs
// behind a glass facade; three lab rooms open off it through 0.75 m doors; the east end is a
// loading hall with a ramp (6 % grade) up to a raised platform and a stairwell going down one
// storey. docs/maps.md has the plan and the labels.
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/mapgen/layout.hpp>

namespace polyloc {

struct LabOptions {
  float wall_height = 2.8f;      // walls and glass facade, m above the floor
  float wall_thickness = 0.15f;  // m
  float door_width = 0.75f;      // clear width of the three lab doors
  float door_height = 2.0f;      // clear height of the lab doors
  float table_height = 0.75f;    // top surface of the lab benches
  float seat_height = 0.45f;     // top of the chair seats
  float ramp_grade = 0.06f;      // rise over run of the loading ramp (0.06 = 3.4 deg)
  float platform_height = 0.3f;  // raised loading platform; ramp length = height / grade
  int cylinder_segments = 16;    // sides of the waste bins
};

// Deterministic: the same options give the same mesh, bit for bit. If layout is given, it
// receives the positions of doors, tables, chairs, the ramp, the platform and the stairwell.
// Throws std::invalid_argument for options that do not fit the floor plan.
Mesh generateLab(const LabOptions& options = {}, MapLayout* layout = nullptr);

}  // namespace polyloc
