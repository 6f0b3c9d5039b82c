#include <polyloc/map/mesh.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>

namespace polyloc {

uint32_t Mesh::labelId(const std::string& name) {
  auto it = std::find(label_names.begin(), label_names.end(), name);
  if (it != label_names.end()) return static_cast<uint32_t>(it - label_names.begin());
  label_names.push_back(name);
  return static_cast<uint32_t>(label_names.size() - 1);
}

int64_t Mesh::findLabel(const std::string& name) const {
  auto it = std::find(label_names.begin(), label_names.end(), name);
  return it == label_names.end() ? -1 : static_cast<int64_t>(it - label_names.begin());
}

Eigen::Vector3f Mesh::triangleNormal(size_t tri) const {
  const Triangle& t = triangles[tri];
  Eigen::Vector3f n = (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  float len = n.norm();
  return len > 0.f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
}

Eigen::AlignedBox3f Mesh::bounds() const {
  Eigen::AlignedBox3f box;
  for (const auto& v : vertices) box.extend(v);
  return box;
}

void Mesh::append(const Mesh& other) {
  const uint32_t base = static_cast<uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  std::vector<uint32_t> remap(other.label_names.size());
  for (size_t i = 0; i < remap.size(); ++i) remap[i] = labelId(other.label_names[i]);
  for (size_t i = 0; i < other.triangles.size(); ++i) {
    const Triangle& t = other.triangles[i];
    triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    triangle_label.push_back(remap[other.triangle_label[i]]);
  }
}

void Mesh::addTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                       uint32_t label) {
  const uint32_t base = static_cast<uint32_t>(vertices.size());
  vertices.push_back(a);
  vertices.push_back(b);
  vertices.push_back(c);
  triangles.push_back({base, base + 1, base + 2});
  triangle_label.push_back(label);
}

void Mesh::addQuad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                   const Eigen::Vector3f& d, uint32_t label) {
  const uint32_t base = static_cast<uint32_t>(vertices.size());
  vertices.insert(vertices.end(), {a, b, c, d});
  triangles.push_back({base, base + 1, base + 2});
  triangles.push_back({base, base + 2, base + 3});
  triangle_label.push_back(label);
  triangle_label.push_back(label);
}

void Mesh::addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, uint32_t label,
                  const Eigen::Vector2d& origin, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const uint32_t b = static_cast<uint32_t>(vertices.size());
  // Vertex k: bit 0 = x, bit 1 = y, bit 2 = z. Quads listed counter-clockwise from outside.
  for (int k = 0; k < 8; ++k) {
    const double x = k & 1 ? hi.x() : lo.x(), y = k & 2 ? hi.y() : lo.y(), z = k & 4 ? hi.z() : lo.z();
    vertices.emplace_back(float(origin.x() + c * x - s * y), float(origin.y() + s * x + c * y), float(z));
  }
  static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    triangles.push_back({b + q[0], b + q[1], b + q[2]});
    triangles.push_back({b + q[0], b + q[2], b + q[3]});
    triangle_label.push_back(label);
    triangle_label.push_back(label);
  }
}

std::string normalizeLabel(const std::string& name) {
  std::string s;
  s.reserve(name.size());
  for (char c : name) s.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  // Strip trailing instance numbers and separators: "door_3", "glass.001", "table-12".
  while (!s.empty() && (std::isdigit(static_cast<unsigned char>(s.back())) || s.back() == '_' ||
                        s.back() == '.' || s.back() == '-' || s.back() == ' '))
    s.pop_back();
  return s;
}

}  // namespace polyloc
