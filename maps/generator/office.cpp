// The `office` map (see office.hpp and docs/maps.md).
#include <polyloc/mapgen/builder.hpp>
#include <polyloc/mapgen/furniture.hpp>
#include <polyloc/mapgen/office.hpp>
#include <polyloc/mapgen/walls.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace polyloc {

using mapgen::MeshBuilder;
using mapgen::Placer;
using V2 = Eigen::Vector2f;

namespace {

constexpr float kPi = static_cast<float>(M_PI);
constexpr float kFloorMargin = 0.3f;
constexpr float kSlab = 0.2f;

void checkOptions(const OfficeOptions& o) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("office options: " + what);
  };
  if (o.rows < 1 || o.cols < 1 || o.rows * o.cols > 10000)
    fail("rows and cols must be at least 1 (and rows * cols at most 10000)");
  if (!(o.wall_thickness >= 0.05f && o.wall_thickness <= 0.3f))
    fail("wall_thickness must be in [0.05, 0.3] m");
  if (!(o.room_width >= 2.6f && o.room_depth >= 3.0f))
    fail("rooms must be at least 2.6 m wide and 3 m deep");
  if (!(o.corridor_width >= 1.0f)) fail("corridor_width must be at least 1 m");
  if (!(o.wall_height >= 2.2f && o.wall_height <= 5.f)) fail("wall_height must be in [2.2, 5] m");
  if (!(o.door_height >= 1.5f && o.door_height <= o.wall_height - 0.1f))
    fail("door_height must be in [1.5, wall_height - 0.1] m");
  if (!(o.door_width >= 0.6f && o.door_width <= o.room_width / 2 - 0.4f))
    fail("door_width must be in [0.6, room_width / 2 - 0.4] m");
  if (o.tables_per_room < 0 || o.tables_per_room > 2) fail("tables_per_room must be 0, 1 or 2");
  if (o.chairs_per_room < 0 || o.chairs_per_room > o.tables_per_room)
    fail("chairs_per_room must be in [0, tables_per_room]");
}

struct Row {
  float y0, y1;       // wall centre lines
  bool door_north;    // the corridor (and the door) is on the north side
};

}  // namespace

Mesh generateOffice(const OfficeOptions& o, MapLayout* layout_out) {
  checkOptions(o);
  const float t = o.wall_thickness, w = o.room_width, d = o.room_depth, cw = o.corridor_width;

  // Rows from south to north: row 2k below corridor k, row 2k+1 above it.
  std::vector<Row> rows;
  float y = 0.f;
  for (int r = 0; r < o.rows; ++r) {
    if (r % 2 == 0) {
      rows.push_back({y, y + d, true});
      y += d + cw;
    } else {
      rows.push_back({y, y + d, false});
      y += d;
    }
  }
  const float x_max = cw + o.cols * w, y_max = y;

  MapLayout layout;
  layout.building = {V2(0.f, 0.f), V2(x_max, y_max)};
  Mesh mesh;
  mesh.source = "generated:office";
  MeshBuilder b(mesh);
  b.box({-kFloorMargin, -kFloorMargin, -kSlab}, {x_max + kFloorMargin, y_max + kFloorMargin, 0.f},
        "floor");

  mapgen::WallStyle style;
  style.thickness = t;
  style.height = o.wall_height;
  mapgen::WallPlan plan(style);
  plan.addWall({0.f, 0.f}, {x_max, 0.f});
  plan.addWall({0.f, y_max}, {x_max, y_max});
  plan.addWall({0.f, 0.f}, {0.f, y_max});
  plan.addWall({x_max, 0.f}, {x_max, y_max});

  Placer p{b, layout};
  mapgen::TableSpec desk;
  desk.length = 1.4f;
  desk.depth = 0.7f;
  p.table_spec = desk;
  p.chair_spec.casters = false;  // keeps the benchmark map near 10,000 triangles
  for (int r = 0; r < o.rows; ++r) {
    const Row& row = rows[r];
    plan.addWall({cw, row.y0}, {x_max, row.y0});
    plan.addWall({cw, row.y1}, {x_max, row.y1});
    for (int c = 0; c <= o.cols; ++c) plan.addWall({cw + c * w, row.y0}, {cw + c * w, row.y1});

    for (int c = 0; c < o.cols; ++c) {
      const float x0 = cw + c * w;
      // Doors near the west or east partition, alternating, so the rooms are not all alike.
      const bool west = (r + c) % 2 == 0;
      const float half = o.door_width / 2;
      const float dx = west ? x0 + t / 2 + 0.3f + half : x0 + w - t / 2 - 0.3f - half;
      const float dy = row.door_north ? row.y1 : row.y0;
      plan.addOpening({dx, dy}, o.door_width, o.door_height);
      // The open leaf stands against the room side of the wall, towards the room's middle.
      const float lx0 = west ? dx + half + 0.01f : dx - half - 0.01f - o.door_width;
      const float ly0 = row.door_north ? dy - t / 2 - 0.05f : dy + t / 2 + 0.01f;
      b.box({lx0, ly0, 0.01f}, {lx0 + o.door_width, ly0 + 0.04f, o.door_height - 0.01f}, "door");
      layout.doors.push_back({"room r" + std::to_string(r) + "c" + std::to_string(c), V2(dx, dy),
                              V2(1.f, 0.f), o.door_width, o.door_height, 0.f, false});

      // Furniture in room coordinates: origin at the inner south-west corner. "Back" is the wall
      // opposite the door; desks stand against the side walls near it.
      p.origin = {x0 + t / 2, row.y0 + t / 2};
      const float iw = w - t, id = d - t;
      const float back_y = row.door_north ? 0.72f : id - 0.72f;  // desk centre, 2 cm off the wall
      for (int k = 0; k < o.tables_per_room; ++k) {
        const bool left = k == 0;
        const float tx = left ? 0.37f : iw - 0.37f;
        p.table(tx, back_y, left ? 0.f : kPi, desk.length, desk.depth);
        if (k < o.chairs_per_room) p.chair(left ? tx + 0.65f : tx - 0.65f, back_y, left ? kPi : 0.f);
      }
      if (o.shelf) {
        mapgen::ShelfSpec low;
        low.width = 0.8f;
        low.height = 1.1f;
        low.boards = 3;
        const float sy = row.door_north ? 0.22f : id - 0.22f;
        mapgen::addShelf(b, p.origin + V2(iw / 2, sy), row.door_north ? kPi / 2 : -kPi / 2, low);
      }
      const float bin_y = row.door_north ? id - 0.3f : 0.3f;  // beside the door, away from the leaf
      p.bin(west ? iw - 0.3f : 0.3f, bin_y, 12);
    }
  }
  plan.build(b);

  if (layout_out) *layout_out = std::move(layout);
  return mesh;
}

}  // namespace polyloc
