// Furniture for the procedural maps, each piece built from closed solids with one label. A piece
// is placed by the point it stands on and a yaw: its local +x is its front (where a person
// sits or reaches in), z = 0 is the floor it stands on (use MeshBuilder::pushFrame for raised
// floors). Parts overlap a little instead of touching, so no two solids share a vertex.
#pragma once

#include <polyloc/mapgen/builder.hpp>
#include <polyloc/mapgen/layout.hpp>

#include <Eigen/Core>

namespace polyloc::mapgen {

struct TableSpec {
  float length = 1.6f;          // along local y (the side people sit at faces +x)
  float depth = 0.8f;           // along local x
  float height = 0.75f;         // top surface
  float top_thickness = 0.035f;
  float leg_size = 0.04f;       // square legs
  float leg_inset = 0.05f;      // from the table edge to the leg's outer face
};
// Table top centred on position; label "table".
void addTable(MeshBuilder& b, const Eigen::Vector2f& position, float yaw, const TableSpec& spec = {});

struct ChairSpec {
  float seat_height = 0.45f;  // top of the seat
  float seat_size = 0.46f;    // square seat
  float seat_thickness = 0.06f;
  float back_top = 0.95f;     // top of the backrest
  float base_radius = 0.32f;  // five-star base, arm length from the column
  bool casters = true;        // a small cylinder under each arm (adds 100 triangles)
  int column_segments = 12;
};
// Office chair whose seat centre (the column) stands at position, facing local +x (the
// backrest is behind, at -x); label "chair".
void addChair(MeshBuilder& b, const Eigen::Vector2f& position, float yaw, const ChairSpec& spec = {});

struct ShelfSpec {
  float width = 1.0f;  // along local y
  float depth = 0.4f;  // along local x; open at +x, back panel at -x
  float height = 2.0f;
  int boards = 5;      // including bottom and top board
  float panel = 0.02f;  // thickness of side panels and boards
};
// Open shelf with side panels, a back panel and boards; label "shelf".
void addShelf(MeshBuilder& b, const Eigen::Vector2f& position, float yaw, const ShelfSpec& spec = {});

// Closed cabinet of size (depth x, width y, height z) on a recessed plinth, with a handle on its
// front (+x); label "cabinet". Fume hoods and fridges are cabinets too.
void addCabinet(MeshBuilder& b, const Eigen::Vector2f& position, float yaw,
                const Eigen::Vector3f& size);

// Waste bin: a closed cylinder; label "bin".
void addBin(MeshBuilder& b, const Eigen::Vector2f& position, float radius = 0.15f,
            float height = 0.4f, int segments = 16);

// Places furniture relative to an origin (a room's inner corner, axes as the map) and records
// tables and chairs in a layout, so generators describe rooms in room coordinates.
struct Placer {
  MeshBuilder& b;
  MapLayout& layout;
  Eigen::Vector2f origin{0.f, 0.f};
  TableSpec table_spec{};
  ChairSpec chair_spec{};

  void table(float x, float y, float yaw, float length, float depth);
  void chair(float x, float y, float yaw);
  void shelf(float x, float y, float yaw, float width = 1.0f, float height = 2.0f);
  void cabinet(float x, float y, float yaw, const Eigen::Vector3f& size);
  void bin(float x, float y, int segments = 16);
};

}  // namespace polyloc::mapgen
