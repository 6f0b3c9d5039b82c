#include <polyloc/mapgen/furniture.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc::mapgen {

void addTable(MeshBuilder& b, const Eigen::Vector2f& position, float yaw, const TableSpec& s) {
  b.pushFrame(position, yaw);
  const float hx = s.depth / 2, hy = s.length / 2;
  b.box({-hx, -hy, s.height - s.top_thickness}, {hx, hy, s.height}, "table");
  // Legs reach halfway into the top, so their top faces hide inside it near table height.
  const float lx = hx - s.leg_inset - s.leg_size / 2, ly = hy - s.leg_inset - s.leg_size / 2;
  for (float sx : {-1.f, 1.f})
    for (float sy : {-1.f, 1.f})
      b.orientedBox({sx * lx, sy * ly}, {s.leg_size, s.leg_size}, 0.f, 0.f,
                    s.height - s.top_thickness / 2, "table");
  b.popFrame();
}

void addChair(MeshBuilder& b, const Eigen::Vector2f& position, float yaw, const ChairSpec& s) {
  b.pushFrame(position, yaw);
  const float h = s.seat_size / 2;
  b.box({-h, -h, s.seat_height - s.seat_thickness}, {h, h, s.seat_height}, "chair");
  // Column from inside the star base to just under the seat top.
  b.cylinder({0.f, 0.f}, 0.025f, 0.07f, s.seat_height - 0.01f, s.column_segments, "chair");
  constexpr int kArms = 5;
  for (int k = 0; k < kArms; ++k) {
    const float a = static_cast<float>(2 * M_PI * k / kArms);
    const Eigen::Vector2f dir(std::cos(a), std::sin(a));
    b.orientedBox(dir * (s.base_radius / 2), {s.base_radius, 0.05f}, a, 0.05f, 0.09f, "chair");
    if (s.casters) b.cylinder(dir * (s.base_radius - 0.03f), 0.025f, 0.f, 0.07f, 6, "chair");
  }
  // Backrest behind the seat on a post that starts inside the seat and ends inside the backrest.
  b.box({-h - 0.04f, -h + 0.02f, s.seat_height + 0.1f}, {-h + 0.02f, h - 0.02f, s.back_top},
        "chair");
  b.box({-h - 0.02f, -0.02f, s.seat_height - 0.04f}, {-h + 0.01f, 0.02f, s.seat_height + 0.15f},
        "chair");
  b.popFrame();
}

void addShelf(MeshBuilder& b, const Eigen::Vector2f& position, float yaw, const ShelfSpec& s) {
  b.pushFrame(position, yaw);
  const float hx = s.depth / 2, hy = s.width / 2, p = s.panel;
  b.box({-hx, hy - p, 0.f}, {hx, hy, s.height}, "shelf");
  b.box({-hx, -hy, 0.f}, {hx, -hy + p, s.height}, "shelf");
  // Boards and back panel reach to the middle of the side panels.
  const float inner = hy - p / 2;
  b.box({-hx + 0.002f, -inner, 0.04f}, {-hx + 0.012f, inner, s.height - 0.005f}, "shelf");
  const int n = std::max(s.boards, 2);
  for (int k = 0; k < n; ++k) {
    const float z = 0.08f + k * (s.height - 0.08f - p) / (n - 1);
    b.box({-hx + 0.005f, -inner, z}, {hx - 0.005f, inner, z + p}, "shelf");
  }
  b.popFrame();
}

void addCabinet(MeshBuilder& b, const Eigen::Vector2f& position, float yaw,
                const Eigen::Vector3f& size) {
  b.pushFrame(position, yaw);
  const float hx = size.x() / 2, hy = size.y() / 2, h = size.z();
  b.box({-hx + 0.05f, -hy + 0.03f, 0.f}, {hx - 0.05f, hy - 0.03f, 0.1f}, "cabinet");
  b.box({-hx, -hy, 0.08f}, {hx, hy, h}, "cabinet");
  const float zh = std::min(h - 0.3f, 1.0f);
  b.box({hx - 0.01f, hy - 0.09f, zh}, {hx + 0.025f, hy - 0.07f, zh + 0.2f}, "cabinet");
  b.popFrame();
}

void addBin(MeshBuilder& b, const Eigen::Vector2f& position, float radius, float height,
            int segments) {
  b.cylinder(position, radius, 0.f, height, segments, "bin");
}

void Placer::table(float x, float y, float yaw, float length, float depth) {
  TableSpec s = table_spec;
  s.length = length;
  s.depth = depth;
  const Eigen::Vector2f p = origin + Eigen::Vector2f(x, y);
  addTable(b, p, yaw, s);
  layout.tables.push_back(p);
}

void Placer::chair(float x, float y, float yaw) {
  const Eigen::Vector2f p = origin + Eigen::Vector2f(x, y);
  addChair(b, p, yaw, chair_spec);
  layout.chairs.push_back(p);
}

void Placer::shelf(float x, float y, float yaw, float width, float height) {
  ShelfSpec s;
  s.width = width;
  s.height = height;
  addShelf(b, origin + Eigen::Vector2f(x, y), yaw, s);
}

void Placer::cabinet(float x, float y, float yaw, const Eigen::Vector3f& size) {
  addCabinet(b, origin + Eigen::Vector2f(x, y), yaw, size);
}

void Placer::bin(float x, float y, int segments) {
  addBin(b, origin + Eigen::Vector2f(x, y), 0.15f, 0.4f, segments);
}

}  // namespace polyloc::mapgen
