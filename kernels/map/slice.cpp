#include <polyloc/map/slice.hpp>

namespace polyloc {

// Each triangle crossing the plane contributes the segment between its two edge crossings.
// Vertices exactly on the plane count as above, so a crossing is never counted twice.
std::vector<SliceSegment> sliceMesh(const Mesh& mesh, float height) {
  std::vector<SliceSegment> out;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    Eigen::Vector2f pts[2];
    int n = 0;
    for (int e = 0; e < 3 && n < 2; ++e) {
      const Eigen::Vector3f& p = mesh.vertices[tri[e]];
      const Eigen::Vector3f& q = mesh.vertices[tri[(e + 1) % 3]];
      const bool pa = p.z() >= height, qa = q.z() >= height;
      if (pa == qa) continue;
      const float s = (height - p.z()) / (q.z() - p.z());
      pts[n++] = (p + s * (q - p)).head<2>();
    }
    if (n == 2) out.push_back({pts[0], pts[1], static_cast<uint32_t>(t), mesh.triangle_label[t]});
  }
  return out;
}

}  // namespace polyloc
