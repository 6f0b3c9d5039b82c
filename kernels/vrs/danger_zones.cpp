#include <polyloc/vrs/danger_zones.hpp>
#include <polyloc/map/grid_walk.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

namespace {

using V2 = Eigen::Vector2f;

float cross(const V2& a, const V2& b) { return a.x() * b.y() - a.y() * b.x(); }

float segmentDistance(const V2& p, const V2& a, const V2& b) {
  const V2 ab = b - a;
  const float len2 = ab.squaredNorm();
  const float t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.f, 1.f) : 0.f;
  return (a + t * ab - p).norm();
}

}  // namespace

DangerZones::DangerZones(const Mesh* map, const std::vector<std::string>& labels,
                         const std::vector<std::vector<Eigen::Vector2d>>& polygons, double resolution)
    : res_(resolution) {
  if (!(resolution > 0)) throw std::invalid_argument("danger zones: resolution must be > 0");
  std::vector<std::vector<V2>> polys;
  for (size_t k = 0; k < polygons.size(); ++k) {
    if (polygons[k].size() < 3) throw std::invalid_argument("danger zone " + std::to_string(k) + ": needs at least 3 corners");
    std::vector<V2> p;
    for (const auto& v : polygons[k]) {
      if (!v.allFinite()) throw std::invalid_argument("danger zone " + std::to_string(k) + ": corner not finite");
      p.push_back(v.cast<float>());
    }
    polys.push_back(std::move(p));
  }
  std::vector<std::array<V2, 3>> tris;
  if (map)
    for (size_t t = 0; t < map->numTriangles(); ++t)
      if (std::find(labels.begin(), labels.end(), map->labelOf(t)) != labels.end()) {
        const auto& tri = map->triangles[t];
        tris.push_back({map->vertices[tri[0]].head<2>(), map->vertices[tri[1]].head<2>(), map->vertices[tri[2]].head<2>()});
      }
  if (polys.empty() && tris.empty()) return;
  Eigen::AlignedBox2f box;
  for (const auto& p : polys)
    for (const V2& v : p) box.extend(v);
  for (const auto& t : tris)
    for (const V2& v : t) box.extend(v);
  lo_ = box.min() - V2::Constant(2 * float(res_));
  nx_ = int32_t(std::ceil((box.max().x() - lo_.x()) / res_)) + 2;
  ny_ = int32_t(std::ceil((box.max().y() - lo_.y()) / res_)) + 2;
  if (double(nx_) * double(ny_) > 4e8) throw std::invalid_argument("danger zones: raster too large, raise danger_resolution");
  cells_.assign(size_t(nx_) * size_t(ny_), 0);
  for (const auto& t : tris) markTriangle(t[0], t[1], t[2]);
  for (const auto& p : polys) markPolygon(p);
}

// Cells whose centre is within half a cell of the triangle: thin railings are not lost.
void DangerZones::markTriangle(const V2& a, const V2& b, const V2& c) {
  const float area = cross(b - a, c - a);
  const float half = 0.5f * float(res_);
  const V2 lo = a.cwiseMin(b).cwiseMin(c) - V2::Constant(half), hi = a.cwiseMax(b).cwiseMax(c) + V2::Constant(half);
  const int32_t i0 = std::max(0, int32_t((lo.x() - lo_.x()) / res_)), i1 = std::min(nx_ - 1, int32_t((hi.x() - lo_.x()) / res_));
  const int32_t j0 = std::max(0, int32_t((lo.y() - lo_.y()) / res_)), j1 = std::min(ny_ - 1, int32_t((hi.y() - lo_.y()) / res_));
  for (int32_t j = j0; j <= j1; ++j)
    for (int32_t i = i0; i <= i1; ++i) {
      const V2 p = lo_ + V2((float(i) + 0.5f) * float(res_), (float(j) + 0.5f) * float(res_));
      const float s0 = cross(b - a, p - a), s1 = cross(c - b, p - b), s2 = cross(a - c, p - c);
      const bool in = area != 0 && ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0));
      if (in || std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)}) <= half)
        cells_[size_t(j) * size_t(nx_) + size_t(i)] = 1;
    }
}

void DangerZones::markPolygon(const std::vector<V2>& poly) {
  // Even-odd rule on cell centres, plus the cells along the outline.
  Eigen::AlignedBox2f box;
  for (const V2& v : poly) box.extend(v);
  const int32_t i0 = std::max(0, int32_t((box.min().x() - lo_.x()) / res_) - 1), i1 = std::min(nx_ - 1, int32_t((box.max().x() - lo_.x()) / res_) + 1);
  const int32_t j0 = std::max(0, int32_t((box.min().y() - lo_.y()) / res_) - 1), j1 = std::min(ny_ - 1, int32_t((box.max().y() - lo_.y()) / res_) + 1);
  const float half = 0.5f * float(res_);
  for (int32_t j = j0; j <= j1; ++j)
    for (int32_t i = i0; i <= i1; ++i) {
      const V2 p = lo_ + V2((float(i) + 0.5f) * float(res_), (float(j) + 0.5f) * float(res_));
      bool in = false;
      float edge = std::numeric_limits<float>::infinity();
      for (size_t k = 0, l = poly.size() - 1; k < poly.size(); l = k++) {
        const V2 &a = poly[k], &b = poly[l];
        if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
        edge = std::min(edge, segmentDistance(p, a, b));
      }
      if (in || edge <= half) cells_[size_t(j) * size_t(nx_) + size_t(i)] = 1;
    }
}

bool DangerZones::at(int32_t cx, int32_t cy) const {
  return cx >= 0 && cy >= 0 && cx < nx_ && cy < ny_ && cells_[size_t(cy) * size_t(nx_) + size_t(cx)];
}

bool DangerZones::inside(const Eigen::Vector2f& p) const {
  if (cells_.empty()) return false;
  return at(int32_t(std::floor((p.x() - lo_.x()) / res_)), int32_t(std::floor((p.y() - lo_.y()) / res_)));
}

size_t DangerZones::cellCount() const { return size_t(std::count(cells_.begin(), cells_.end(), uint8_t{1})); }

float DangerZones::castRay(const Eigen::Vector2f& origin, float angle, float max_distance) const {
  const float inf = std::numeric_limits<float>::infinity();
  if (cells_.empty() || !origin.allFinite()) return inf;
  const V2 d(std::cos(angle), std::sin(angle));
  // Only the part of the ray over the raster is walked (most rays miss it altogether).
  const V2 hi_box = lo_ + V2(float(nx_) * float(res_), float(ny_) * float(res_));
  float t_in = 0, t_out = max_distance;
  for (int a = 0; a < 2; ++a) {
    if (std::abs(d[a]) < 1e-9f) {
      if (origin[a] < lo_[a] || origin[a] > hi_box[a]) return inf;
      continue;
    }
    float ta = (lo_[a] - origin[a]) / d[a], tb = (hi_box[a] - origin[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t_in = std::max(t_in, ta), t_out = std::min(t_out, tb);
  }
  if (t_in > t_out) return inf;
  const V2 start = origin + t_in * d, end = origin + t_out * d;
  const int32_t x0 = int32_t(std::floor((start.x() - lo_.x()) / res_)), y0 = int32_t(std::floor((start.y() - lo_.y()) / res_));
  const int32_t x1 = int32_t(std::floor((end.x() - lo_.x()) / res_)), y1 = int32_t(std::floor((end.y() - lo_.y()) / res_));
  float range = inf;
  walkCells(x0, y0, x1, y1, [&](int32_t cx, int32_t cy) {
    if (!at(cx, cy)) return false;
    // Entry of the ray into this cell's box (slab method): the zone's near edge.
    const V2 lo = lo_ + V2(float(cx) * float(res_), float(cy) * float(res_)), hi = lo + V2::Constant(float(res_));
    float t0 = 0, t1 = max_distance;
    for (int a = 0; a < 2; ++a) {
      if (std::abs(d[a]) < 1e-9f) continue;
      float ta = (lo[a] - origin[a]) / d[a], tb = (hi[a] - origin[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    // Bresenham may step diagonally past a corner the ray does not cross: take the cell's
    // nearest point to the ray then (within a cell of the truth).
    const float t = t0 <= t1 ? t0 : std::max(0.f, (0.5f * (lo + hi) - origin).dot(d) - 0.5f * float(res_));
    if (t <= max_distance) range = t;
    return t <= max_distance;
  });
  return range;
}

}  // namespace polyloc
