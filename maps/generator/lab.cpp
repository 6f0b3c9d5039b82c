// The `lab` map (see lab.hpp and docs/maps.md). Rooms are described in room coordinates: x from
// the room's west wall face, y from its south wall face, both in metres.
#include <polyloc/mapgen/builder.hpp>
#include <polyloc/mapgen/furniture.hpp>
#include <polyloc/mapgen/lab.hpp>
#include <polyloc/mapgen/walls.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {

using mapgen::MeshBuilder;
using mapgen::Placer;
using V2 = Eigen::Vector2f;
using V3 = Eigen::Vector3f;

namespace {

constexpr float kPi = static_cast<float>(M_PI);
constexpr float kLength = 26.f;   // x, outer wall centre lines
constexpr float kWidth = 14.f;    // y
constexpr float kCorridorWall = 3.5f;  // y of the wall between corridor and labs
constexpr float kRoomX[4] = {0.f, 6.5f, 13.f, 19.5f};  // lab partitions; the hall is east of 19.5
constexpr float kDoorX[3] = {5.0f, 8.0f, 17.5f};       // lab door centres (not symmetric on purpose)
constexpr float kFloorMargin = 0.4f;  // the slab reaches this far beyond the outer walls
constexpr float kSlab = 0.2f;         // slab thickness below z = 0

// Stairwell: 17 risers of 3/17 m down one storey, 16 treads of 0.28 m, then a landing.
constexpr float kStairDepth = 3.0f;
constexpr int kRisers = 17;
constexpr float kTread = 0.28f;
const V2 kHoleLo{23.9f, 4.0f};
const V2 kHoleHi{25.6f, 4.0f + (kRisers - 1) * kTread + 1.2f};

// Loading hall: platform along the north wall, ramp rising north onto it, loading door east.
constexpr float kPlatformY = 10.5f;
constexpr float kRampX0 = 20.6f, kRampX1 = 22.6f;
constexpr float kLoadingDoorY = 12.2f, kLoadingDoorWidth = 2.4f;

void checkOptions(const LabOptions& o) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("lab options: " + what);
  };
  if (!(o.wall_thickness >= 0.05f && o.wall_thickness <= 0.3f))
    fail("wall_thickness must be in [0.05, 0.3] m");
  if (!(o.wall_height >= 2.2f && o.wall_height <= 5.f)) fail("wall_height must be in [2.2, 5] m");
  if (!(o.door_height >= 1.5f && o.door_height <= o.wall_height - 0.1f))
    fail("door_height must be in [1.5, wall_height - 0.1] m");
  if (!(o.door_width >= 0.5f && o.door_width <= 1.2f)) fail("door_width must be in [0.5, 1.2] m");
  if (!(o.table_height >= 0.5f && o.table_height <= 1.1f))
    fail("table_height must be in [0.5, 1.1] m");
  if (!(o.seat_height >= 0.3f && o.seat_height <= 0.7f)) fail("seat_height must be in [0.3, 0.7] m");
  if (!(o.platform_height >= 0.05f && o.platform_height <= 1.f))
    fail("platform_height must be in [0.05, 1] m");
  if (!(o.ramp_grade > 0.f) || o.platform_height / o.ramp_grade > kPlatformY - kCorridorWall - 0.5f)
    fail("ramp_grade too small: the ramp must fit between corridor and platform (6.5 m)");
  if (o.cylinder_segments < 3) fail("cylinder_segments must be at least 3");
}

// Corridor facade along y = 0: parapet, mullions and a top beam (wall) holding glass panes.
void buildFacade(MeshBuilder& b, const LabOptions& o) {
  const float t = o.wall_thickness, h = o.wall_height;
  b.box({-t / 2, -t / 2, 0.f}, {kLength + t / 2, t / 2, 0.9f}, "wall");
  b.box({-t / 2, -t / 2, h - 0.25f}, {kLength + t / 2, t / 2, h}, "wall");
  constexpr int kBays = 20;
  const float bay = kLength / kBays;
  for (int i = 1; i < kBays; ++i)
    b.box({i * bay - 0.04f, -0.05f, 0.85f}, {i * bay + 0.04f, 0.05f, h - 0.2f}, "wall");
  // Panes reach into the mullions and the end walls; thinner than them, so faces do not coincide.
  for (int i = 0; i < kBays; ++i) {
    const float x0 = i == 0 ? t / 2 - 0.03f : i * bay + 0.02f;
    const float x1 = i == kBays - 1 ? kLength - t / 2 + 0.03f : (i + 1) * bay - 0.02f;
    b.box({x0, -0.01f, 0.88f}, {x1, 0.01f, h - 0.22f}, "glass");
  }
}

// Opening in the floor with one solid flight of stairs down to a landing (all "danger"), shaft
// walls below the slab and a railing around the three sides that are not the way down.
void buildStairwell(MeshBuilder& b, MapLayout& layout) {
  const V2 lo = kHoleLo, hi = kHoleHi;
  const float rise = kStairDepth / kRisers;
  b.box({lo.x() - 0.4f, lo.y() - 0.4f, -kStairDepth - 0.2f},
        {hi.x() + 0.4f, hi.y() + 0.4f, -kStairDepth}, "danger");
  b.pushFrame(lo, kPi / 2);  // local x runs north down the flight, local y = west
  const float w = hi.x() - lo.x();
  b.stairs(0.f, -(w - 0.01f), -0.01f, 0.f, kRisers - 1, -rise, kTread, -kStairDepth, "danger");
  b.popFrame();

  constexpr float ts = 0.15f;  // shaft walls, below the slab
  const float z0 = -kStairDepth, z1 = -kSlab;
  b.box({lo.x() - ts, lo.y() - ts, z0}, {hi.x() + ts, lo.y(), z1}, "wall");
  b.box({lo.x() - ts, hi.y(), z0}, {hi.x() + ts, hi.y() + ts, z1}, "wall");
  b.box({lo.x() - ts, lo.y() - ts / 2, z0}, {lo.x(), hi.y() + ts / 2, z1}, "wall");
  b.box({hi.x(), lo.y() - ts / 2, z0}, {hi.x() + ts, hi.y() + ts / 2, z1}, "wall");

  // Railing 5 cm outside the hole: handrail at 1 m, knee rail at 0.5 m, posts at most 1.2 m apart.
  const float xw = lo.x() - 0.05f, xe = hi.x() + 0.05f, yn = hi.y() + 0.05f;
  for (auto [half, z] : {std::pair{0.025f, 0.95f}, std::pair{0.015f, 0.48f}}) {
    const float zt = z + 2 * half;
    b.box({xw - half, yn - half, z}, {xe + half, yn + half, zt}, "danger");  // north, over corners
    b.box({xw - half, lo.y(), z}, {xw + half, yn, zt}, "danger");
    b.box({xe - half, lo.y(), z}, {xe + half, yn, zt}, "danger");
  }
  auto posts = [&](V2 from, V2 to) {
    const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / 1.2f)));
    for (int i = 0; i <= n; ++i) {
      if (i > 0 && from == to) break;
      const V2 p = from + (to - from) * (float(i) / float(n));
      b.box({p.x() - 0.02f, p.y() - 0.02f, 0.f}, {p.x() + 0.02f, p.y() + 0.02f, 0.98f}, "danger");
    }
  };
  posts({xw, lo.y() + 0.03f}, {xw, yn});
  posts({xe, lo.y() + 0.03f}, {xe, yn});
  posts({xw + (xe - xw) / 2, yn}, {xw + (xe - xw) / 2, yn});  // middle of the north side
  layout.stairwells.push_back({lo, hi});
}

// Platform (floor) along the north of the hall and the ramp rising north onto it.
void buildLoading(MeshBuilder& b, const LabOptions& o, MapLayout& layout) {
  const float h = o.platform_height, run = h / o.ramp_grade;
  b.box({kRoomX[3], kPlatformY, 0.f}, {kLength, kWidth, h}, "floor");
  b.pushFrame({0.f, 0.f}, kPi / 2);  // the ramp rises along local x = world north
  b.ramp({kPlatformY - run, -kRampX1}, {kPlatformY, -kRampX0}, 0.f, 0.f, h, "ramp");
  b.popFrame();
  layout.platforms.push_back({V2(kRoomX[3], kPlatformY), V2(kLength, kWidth)});
  layout.ramps.push_back({V2(kRampX0, kPlatformY - run), V2(kRampX1, kPlatformY)});
}

void furnishLabs(MeshBuilder& b, const LabOptions& o, MapLayout& layout) {
  const float t = o.wall_thickness;
  const float w = kRoomX[1] - kRoomX[0] - t, d = kWidth - kCorridorWall - t;  // inner room size
  Placer p{b, layout};
  p.table_spec.height = o.table_height;
  p.chair_spec.seat_height = o.seat_height;
  p.chair_spec.back_top = o.seat_height + 0.5f;
  const int seg = o.cylinder_segments;
  const V3 hood{0.8f, 1.5f, 2.4f}, tall{0.6f, 1.0f, 2.0f};

  // Lab 1: bench along the west wall, an island of two benches back to back.
  p.origin = {kRoomX[0] + t / 2, kCorridorWall + t / 2};
  for (float y : {2.6f, 4.25f, 5.9f}) p.table(0.395f, y, 0.f, 1.6f, 0.75f);
  p.chair(1.07f, 2.6f, kPi);
  p.chair(1.07f, 5.9f, kPi);
  p.table(3.195f, 6.0f, kPi, 1.8f, 0.8f);
  p.table(4.005f, 6.0f, 0.f, 1.8f, 0.8f);
  p.chair(2.495f, 5.7f, 0.f);
  p.chair(4.705f, 6.3f, kPi);
  for (float x : {0.8f, 1.85f, 2.9f}) p.shelf(x, d - 0.22f, -kPi / 2);
  p.cabinet(w - 0.42f, 7.2f, kPi, hood);
  p.cabinet(w - 0.32f, 9.0f, kPi, tall);
  p.bin(w - 0.3f, 0.35f, seg);
  p.bin(0.3f, 8.5f, seg);

  // Lab 2: one long bench in the middle, shelves east, cabinets north, a fridge west.
  p.origin = {kRoomX[1] + t / 2, kCorridorWall + t / 2};
  for (float y : {3.0f, 4.85f, 6.7f}) p.table(3.2f, y, 0.f, 1.8f, 0.8f);
  p.chair(3.9f, 3.0f, kPi);
  p.chair(3.9f, 6.7f, kPi);
  p.chair(2.5f, 4.85f, 0.f);
  for (float y : {2.5f, 3.55f, 4.6f, 5.65f}) p.shelf(w - 0.22f, y, kPi);
  for (float x : {1.0f, 2.25f, 3.5f}) p.cabinet(x, d - 0.32f, -kPi / 2, {0.6f, 1.2f, 2.0f});
  p.cabinet(0.37f, 8.0f, 0.f, {0.7f, 0.7f, 1.9f});
  p.bin(0.3f, 0.4f, seg);
  p.bin(w - 0.3f, 9.9f, seg);

  // Lab 3: L-shaped bench along north and west walls, an island, shelves and hood east.
  p.origin = {kRoomX[2] + t / 2, kCorridorWall + t / 2};
  for (float x : {1.2f, 3.05f, 4.9f}) p.table(x, d - 0.42f, -kPi / 2, 1.8f, 0.8f);
  p.chair(1.2f, d - 1.12f, kPi / 2);
  p.chair(4.9f, d - 1.12f, kPi / 2);
  for (float y : {4.5f, 6.35f}) p.table(0.42f, y, 0.f, 1.8f, 0.8f);
  p.chair(1.12f, 4.5f, kPi);
  p.table(3.6f, 5.5f, 0.f, 2.0f, 1.0f);
  p.chair(4.4f, 5.0f, kPi);
  for (float y : {1.5f, 2.55f, 3.6f}) p.shelf(w - 0.22f, y, kPi);
  p.cabinet(w - 0.42f, 5.6f, kPi, hood);
  p.cabinet(w - 0.32f, 7.3f, kPi, tall);
  p.bin(w - 0.3f, 0.35f, seg);
  p.bin(0.35f, 8.6f, seg);

  // Corridor: a hose cabinet between the doors and two bins.
  p.origin = {0.f, 0.f};
  p.cabinet(10.5f, kCorridorWall - t / 2 - 0.22f, -kPi / 2, {0.4f, 1.0f, 1.2f});
  p.bin(0.45f, kCorridorWall - t / 2 - 0.3f, seg);
  p.bin(12.0f, kCorridorWall - t / 2 - 0.3f, seg);

  // Platform: storage shelves west, cabinets north, a bin; standing on the platform top.
  b.pushFrame({0.f, 0.f}, 0.f, o.platform_height);
  p.shelf(kRoomX[3] + t / 2 + 0.22f, 12.3f, 0.f);
  p.shelf(kRoomX[3] + t / 2 + 0.22f, 13.35f, 0.f);
  for (float x : {22.4f, 23.7f}) p.cabinet(x, kWidth - t / 2 - 0.32f, -kPi / 2, {0.6f, 1.2f, 1.8f});
  p.bin(24.8f, 11.0f, seg);
  b.popFrame();
}

}  // namespace

Mesh generateLab(const LabOptions& o, MapLayout* layout_out) {
  checkOptions(o);
  MapLayout layout;
  layout.building = {V2(0.f, 0.f), V2(kLength, kWidth)};
  Mesh mesh;
  mesh.source = "generated:lab";
  MeshBuilder b(mesh);
  const float t = o.wall_thickness;

  b.slabWithHole({-kFloorMargin, -kFloorMargin}, {kLength + kFloorMargin, kWidth + kFloorMargin},
                 kHoleLo, kHoleHi, -kSlab, 0.f, "floor");

  mapgen::WallStyle style;
  style.thickness = t;
  style.height = o.wall_height;
  mapgen::WallPlan plan(style);
  plan.addGuide({0.f, 0.f}, {kLength, 0.f});  // the facade, built below
  plan.addWall({0.f, 0.f}, {0.f, kWidth});
  plan.addWall({kLength, 0.f}, {kLength, kWidth});
  plan.addWall({0.f, kWidth}, {kLength, kWidth});
  plan.addWall({0.f, kCorridorWall}, {kRoomX[3], kCorridorWall});
  for (int i = 1; i < 4; ++i) plan.addWall({kRoomX[i], kCorridorWall}, {kRoomX[i], kWidth});

  // Lab doors: open leaves stand against the lab side of the wall (hinges alternate).
  const float leaf_y = kCorridorWall + t / 2 + 0.01f;
  for (int i = 0; i < 3; ++i) {
    const float x = kDoorX[i], half = o.door_width / 2;
    plan.addOpening({x, kCorridorWall}, o.door_width, o.door_height);
    const float x0 = i == 1 ? x + half + 0.01f : x - half - 0.01f - o.door_width;
    b.box({x0, leaf_y, 0.01f}, {x0 + o.door_width, leaf_y + 0.04f, o.door_height - 0.01f}, "door");
    layout.doors.push_back({"lab " + std::to_string(i + 1), V2(x, kCorridorWall), V2(1.f, 0.f),
                            o.door_width, o.door_height, 0.f, false});
  }
  // Loading door on the east wall, closed: a leaf in the opening, reaching into the wall.
  const float load_h = std::min(2.6f, o.wall_height - 0.15f);
  plan.addOpening({kLength, kLoadingDoorY}, kLoadingDoorWidth, load_h);
  b.box({kLength - 0.02f, kLoadingDoorY - kLoadingDoorWidth / 2 - 0.03f, 0.01f},
        {kLength + 0.02f, kLoadingDoorY + kLoadingDoorWidth / 2 + 0.03f, load_h + 0.02f}, "door");
  layout.doors.push_back({"loading bay", V2(kLength, kLoadingDoorY), V2(0.f, 1.f),
                          kLoadingDoorWidth, load_h, 0.f, true});

  plan.build(b);
  buildFacade(b, o);
  buildStairwell(b, layout);
  buildLoading(b, o, layout);
  furnishLabs(b, o, layout);

  if (layout_out) *layout_out = std::move(layout);
  return mesh;
}

}  // namespace polyloc
