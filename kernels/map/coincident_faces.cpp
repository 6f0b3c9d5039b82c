#include <polyloc/map/coincident_faces.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace polyloc {

std::vector<uint8_t> coincidentFaces(const Mesh& mesh, float tolerance) {
  const size_t n = mesh.triangles.size();
  std::vector<uint8_t> out(n, 0);
  // Planes by their normal up to sign (rounded to 1e-3): a face and the face against it fall
  // into one group, told apart by `facing`.
  struct Face {
    size_t tri;
    float offset;  // along the group's normal
    int facing;    // +1 / -1 against the group's normal
    Eigen::AlignedBox3f box;
  };
  std::map<std::array<long, 3>, std::vector<Face>> planes;
  for (size_t t = 0; t < n; ++t) {
    const Eigen::Vector3f nrm = mesh.triangleNormal(t);
    if (!(nrm.squaredNorm() > 0.5f)) continue;  // degenerate: no plane
    int sign = 0;
    for (int k = 0; k < 3 && sign == 0; ++k)
      if (std::abs(nrm[k]) > 1e-6f) sign = nrm[k] > 0 ? 1 : -1;
    const Eigen::Vector3f c = float(sign) * nrm;
    Face f{t, c.dot(mesh.vertices[mesh.triangles[t][0]]), sign, {}};
    for (int k = 0; k < 3; ++k) f.box.extend(mesh.vertices[mesh.triangles[t][k]]);
    planes[{std::lround(c.x() * 1e3f), std::lround(c.y() * 1e3f), std::lround(c.z() * 1e3f)}].push_back(f);
  }
  for (auto& [key, faces] : planes) {
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.offset < b.offset; });
    for (size_t i = 0; i < faces.size(); ++i)
      for (size_t j = i + 1; j < faces.size() && faces[j].offset - faces[i].offset <= tolerance; ++j) {
        if (faces[i].facing == faces[j].facing) continue;
        // Coplanar boxes overlap with area when two of their extents overlap by more than the
        // tolerance (the third is the plane's thickness).
        const Eigen::AlignedBox3f o = faces[i].box.intersection(faces[j].box);
        int spread = 0;
        for (int k = 0; k < 3; ++k) spread += o.max()[k] - o.min()[k] > tolerance;
        if (spread >= 2) out[faces[i].tri] = out[faces[j].tri] = 1;
      }
  }
  return out;
}

}  // namespace polyloc
