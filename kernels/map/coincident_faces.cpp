#include <polyloc/map/coincident_faces.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace polyloc {

float coincidenceTolerance(const Mesh& mesh, float at_least) {
  float scale = 0;
  for (const Eigen::Vector3f& v : mesh.vertices)
    if (v.allFinite()) scale = std::max(scale, v.cwiseAbs().maxCoeff());
  // One float step: the two faces of anything thinner are not told apart at that scale anyway;
  // more would merge a thin wall's two faces into a tie.
  return std::max(at_least, std::nextafter(scale, INFINITY) - scale);
}

CoincidentFaces::CoincidentFaces(const Mesh& mesh, float tolerance) {
  const size_t n = mesh.triangles.size();
  tol_ = tolerance = coincidenceTolerance(mesh, tolerance);
  // Planes by their normal up to sign (rounded to 1e-3) and offset: a face and the face against
  // it sort next to each other, told apart by `facing`.
  struct Face {
    uint64_t normal;  // the rounded normal's three components, 21 bits each
    double offset;    // along the rounded normal's direction (double: no rounding of its own)
    int facing;       // +1 / -1 along it
    uint32_t tri;
  };
  std::vector<Face> faces;
  faces.reserve(n);
  for (size_t t = 0; t < n; ++t) {
    const Eigen::Vector3f nrm = mesh.triangleNormal(t);
    if (!(nrm.squaredNorm() > 0.5f)) continue;  // degenerate: no plane
    int sign = 0;
    for (int k = 0; k < 3 && sign == 0; ++k)
      if (std::abs(nrm[k]) > 1e-6f) sign = nrm[k] > 0 ? 1 : -1;
    const Eigen::Vector3f c = float(sign) * nrm;
    uint64_t key = 0;
    for (int k = 0; k < 3; ++k) key = key << 21 | uint64_t(std::lround(c[k] * 1e3f) + 1000);  // 0..2000
    faces.push_back({key, c.cast<double>().dot(mesh.vertices[mesh.triangles[t][0]].cast<double>()), sign, uint32_t(t)});
  }
  std::sort(faces.begin(), faces.end(),
            [](const Face& a, const Face& b) { return std::pair(a.normal, a.offset) < std::pair(b.normal, b.offset); });
  std::vector<Eigen::AlignedBox3f> box(n);
  for (size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) box[t].extend(mesh.vertices[mesh.triangles[t][k]]);
  // A plane's faces (same rounded normal, offsets within the tolerance of the first), split by
  // facing: only pairs facing opposite ways are compared (a floor of many tiles facing up is not
  // compared with itself). Coplanar boxes overlap with area when two of their extents overlap by
  // more than the tolerance (the third is the plane's thickness).
  std::vector<std::pair<uint32_t, Eigen::AlignedBox3f>> found;
  std::vector<uint32_t> up, down;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    up.clear(), down.clear();
    for (; j < faces.size() && faces[j].normal == faces[i].normal && faces[j].offset - faces[i].offset <= tolerance; ++j)
      (faces[j].facing > 0 ? up : down).push_back(faces[j].tri);
    for (uint32_t a : up)
      for (uint32_t b : down) {
        const Eigen::AlignedBox3f o = box[a].intersection(box[b]);
        int spread = 0;
        for (int k = 0; k < 3; ++k) spread += o.max()[k] - o.min()[k] > tolerance;
        if (spread >= 2) found.emplace_back(a, o), found.emplace_back(b, o);
      }
    i = j;
  }
  has_.assign(n, 0);
  for (const auto& [t, o] : found) {
    has_[t] = 1;
    parts_.push_back({t, o});
    bounds_.extend(o);
  }
  if (parts_.empty()) return;
  // Cells of at least 0.5 m, at most about 100,000 of them (built with the scene: keep it cheap).
  const float kMargin = std::max(1e-4f, 2 * tol_);  // covers()' default margin, grown as it is
  bounds_.min().array() -= 2 * kMargin, bounds_.max().array() += 2 * kMargin;
  const Eigen::Vector3f size = bounds_.sizes();
  cell_ = std::max(0.5f, std::cbrt(size.prod() / 1e5f));
  dims_ = (size / cell_).array().ceil().cast<int>().max(1);
  const auto cellOf = [&](const Eigen::Vector3f& q) {
    return ((q - bounds_.min()) / cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1).matrix().eval();
  };
  const auto forCells = [&](const Eigen::AlignedBox3f& box, auto&& f) {
    const Eigen::Vector3i a = cellOf(box.min().array() - kMargin), b = cellOf(box.max().array() + kMargin);
    for (int z = a.z(); z <= b.z(); ++z)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int x = a.x(); x <= b.x(); ++x) f(size_t((z * dims_.y() + y) * dims_.x() + x));
  };
  cell_first_.assign(size_t(dims_.prod()) + 1, 0);
  for (const Part& q : parts_) forCells(q.box, [&](size_t c) { ++cell_first_[c + 1]; });
  for (size_t c = 1; c < cell_first_.size(); ++c) cell_first_[c] += cell_first_[c - 1];
  cell_parts_.resize(cell_first_.back());
  std::vector<uint32_t> fill(cell_first_.begin(), cell_first_.end() - 1);
  for (uint32_t k = 0; k < parts_.size(); ++k) forCells(parts_[k].box, [&](size_t c) { cell_parts_[fill[c]++] = k; });
  // Each cell's parts by triangle, their triangles beside them: covers() finds a triangle's parts
  // by a binary search over 4-byte keys (a floor cell can list a hundred parts of other faces).
  cell_tris_.resize(cell_parts_.size());
  for (size_t c = 0; c + 1 < cell_first_.size(); ++c) {
    const auto first = cell_parts_.begin() + cell_first_[c], last = cell_parts_.begin() + cell_first_[c + 1];
    std::sort(first, last, [&](uint32_t a, uint32_t b) { return std::pair(parts_[a].tri, a) < std::pair(parts_[b].tri, b); });
  }
  for (size_t k = 0; k < cell_parts_.size(); ++k) cell_tris_[k] = parts_[cell_parts_[k]].tri;
}

bool CoincidentFaces::covers(uint32_t tri, const Eigen::Vector3f& p, float margin) const {
  margin = std::max(margin, 2 * tol_);  // a hit point computed there is a step or two off
  if (!has(tri) || !bounds_.contains(p)) return false;
  const Eigen::Vector3i c = ((p - bounds_.min()) / cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1);
  const size_t cell = size_t((c.z() * dims_.y() + c.y()) * dims_.x() + c.x());
  const auto first = cell_tris_.begin() + cell_first_[cell], last = cell_tris_.begin() + cell_first_[cell + 1];
  for (auto k = std::lower_bound(first, last, tri); k != last && *k == tri; ++k) {
    const Part& q = parts_[cell_parts_[size_t(k - cell_tris_.begin())]];
    if ((p.array() >= q.box.min().array() - margin).all() && (p.array() <= q.box.max().array() + margin).all()) return true;
  }
  return false;
}

size_t CoincidentFaces::triangles() const { return size_t(std::count(has_.begin(), has_.end(), uint8_t{1})); }

}  // namespace polyloc
