// A polygon map: an indexed triangle mesh in the map frame (z up, metres) with a semantic
// label per triangle. Labels come from object or material names (door, glass, danger, floor...)
// and let sensor models and the VRS treat glass, doors and danger zones specially.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

using Triangle = std::array<uint32_t, 3>;

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Triangle> triangles;           // counter-clockwise seen from outside (normal out)
  std::vector<uint32_t> triangle_label;      // per triangle: index into label_names
  std::vector<std::string> label_names{""};  // label 0 is "" (unlabelled)
  std::string source;                        // file it came from, for messages

  size_t numTriangles() const { return triangles.size(); }
  size_t numVertices() const { return vertices.size(); }
  const std::string& labelOf(size_t tri) const { return label_names[triangle_label[tri]]; }
  // Id of a label name, added if new.
  uint32_t labelId(const std::string& name);
  // Id of a label name, or -1 if the map has no such label.
  int64_t findLabel(const std::string& name) const;
  // Unit normal (right-hand rule on the vertex order); zero for degenerate triangles.
  Eigen::Vector3f triangleNormal(size_t tri) const;
  Eigen::AlignedBox3f bounds() const;
  // Append another mesh (labels merged by name).
  void append(const Mesh& other);
  // Append one triangle / quad (two triangles, v0..v3 counter-clockwise) with a label.
  void addTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                   uint32_t label);
  void addQuad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
               const Eigen::Vector3f& d, uint32_t label);
  // Append a closed box [lo, hi] given in a frame turned by yaw about z and shifted by origin
  // (x, y): 12 triangles, counter-clockwise from outside, on 8 vertices of its own.
  void addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, uint32_t label,
              const Eigen::Vector2d& origin = Eigen::Vector2d::Zero(), double yaw = 0.0);
};

// The label's class: the object or material name lowercased, with trailing digits and
// separators removed ("Door_3" -> "door", "glass.001" -> "glass").
std::string normalizeLabel(const std::string& object_or_material_name);

}  // namespace polyloc
