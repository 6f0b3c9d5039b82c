#include <polyloc/map/slice.hpp>
#include <polyloc/raycast/grid2d.hpp>
#include "grid_dt.hpp"


#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint32_t kSolidCell = 0xFFFFFFFEu;  // occupied, but by no particular triangle
constexpr float kMinHorizontal = 0.01f;       // |d_xy| below this: a (near) vertical ray, a miss

struct Hit {
  float s = kInf;  // planar distance along the unit planar direction
  uint32_t cell_tri = kNoHit;
  float nx = 0, ny = 0;
};

}  // namespace

struct Grid2dCaster::Impl {
  size_t nx = 0, ny = 0;
  float res = 0.05f, ox = 0, oy = 0;  // corner of cell (0, 0)
  std::vector<uint32_t> cell;         // kNoHit free, else triangle or kSolidCell
  std::vector<float> clearance;       // m to the nearest occupied cell (0 in one)
  std::vector<uint32_t> labels;       // per mesh triangle

  bool occ(long x, long y) const { return cell[size_t(y) * nx + size_t(x)] != kNoHit; }

  void mark(float x, float y, uint32_t tri) {
    const long i = long(std::floor((x - ox) / res)), j = long(std::floor((y - oy) / res));
    if (i < 0 || j < 0 || i >= long(nx) || j >= long(ny)) return;
    uint32_t& c = cell[size_t(j) * nx + size_t(i)];
    if (c == kNoHit || c == kSolidCell) c = tri;
  }

  void rasterise(const std::vector<SliceSegment>& segs) {
    for (const SliceSegment& s : segs) {
      const float len = (s.b - s.a).norm();
      const int n = std::max(1, int(std::ceil(len / (0.25f * res))));  // every cell it crosses
      for (int k = 0; k <= n; ++k) {
        const Eigen::Vector2f p = s.a + (s.b - s.a) * (float(k) / float(n));
        mark(p.x(), p.y(), s.triangle);
      }
    }
  }

  // Non-zero winding per cell row; segments oriented so that the solid lies on their left.
  void fill(const Mesh& mesh, std::vector<SliceSegment> segs) {
    for (SliceSegment& s : segs) {
      const Eigen::Vector3f n = mesh.triangleNormal(s.triangle);
      const Eigen::Vector2f d = s.b - s.a;
      if (d.y() * n.x() - d.x() * n.y() < 0) std::swap(s.a, s.b);  // outward normal on the right
    }
    std::vector<std::pair<float, int>> xs;
    for (size_t j = 0; j < ny; ++j) {
      const float yc = oy + (float(j) + 0.5f) * res;
      xs.clear();
      for (const SliceSegment& s : segs)
        if ((s.a.y() <= yc) != (s.b.y() <= yc)) {
          const float x = s.a.x() + (yc - s.a.y()) * (s.b.x() - s.a.x()) / (s.b.y() - s.a.y());
          xs.emplace_back(x, s.b.y() > s.a.y() ? 1 : -1);
        }
      std::sort(xs.begin(), xs.end());
      int w = 0;
      for (size_t k = 0; k + 1 < xs.size(); ++k) {
        w += xs[k].second;
        if (w == 0) continue;
        const long i0 = std::max(0L, long(std::ceil((xs[k].first - ox) / res - 0.5f)));
        const long i1 = std::min(long(nx) - 1, long(std::floor((xs[k + 1].first - ox) / res - 0.5f)));
        for (long i = i0; i <= i1; ++i)
          if (cell[j * nx + size_t(i)] == kNoHit) cell[j * nx + size_t(i)] = kSolidCell;
      }
    }
  }

  void finishBuild() {
    std::vector<uint8_t> occupied(cell.size());
    for (size_t i = 0; i < cell.size(); ++i) occupied[i] = cell[i] != kNoHit;
    clearance = gridDistanceTransform(occupied, nx, ny, res);
  }

  // Bresenham walk of the planar ray o + s u, s in [s0, s1].
  Hit walk(float px, float py, float ux, float uy, float s0, float s1, bool skip_inside) const {
    Hit h;
    // Clip the window to the grid box.
    float a = s0, b = s1;
    const float lo[2] = {ox, oy}, hi[2] = {ox + float(nx) * res, oy + float(ny) * res};
    const float p[2] = {px, py}, u[2] = {ux, uy};
    for (int k = 0; k < 2; ++k) {
      if (std::abs(u[k]) < 1e-12f) {
        if (p[k] < lo[k] || p[k] >= hi[k]) return h;
        continue;
      }
      float ta = (lo[k] - p[k]) / u[k], tb = (hi[k] - p[k]) / u[k];
      if (ta > tb) std::swap(ta, tb);
      a = std::max(a, ta);
      b = std::min(b, tb);
    }
    if (!(a <= b)) return h;
    const auto cellOf = [&](float s, long& i, long& j) {
      i = std::clamp(long(std::floor((px + s * ux - ox) / res)), 0L, long(nx) - 1);
      j = std::clamp(long(std::floor((py + s * uy - oy) / res)), 0L, long(ny) - 1);
    };
    long x0, y0, x1, y1;
    cellOf(a, x0, y0);
    cellOf(b, x1, y1);
    const long dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const long sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    long err = dx + dy;
    bool leading = true;  // still in the run of occupied cells the ray starts in
    for (;;) {
      if (occ(x0, y0)) {
        if (!(leading && skip_inside)) return entry(px, py, ux, uy, x0, y0, s0, s1);
      } else {
        leading = false;
      }
      if (x0 == x1 && y0 == y1) break;
      const long e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
    return h;
  }

  // Where the ray enters cell (i, j): slab test; the centre's projection if it only touches it.
  Hit entry(float px, float py, float ux, float uy, long i, long j, float s0, float s1) const {
    Hit h;
    const float bx = ox + float(i) * res, by = oy + float(j) * res;
    float tx0 = -kInf, tx1 = kInf, ty0 = -kInf, ty1 = kInf;
    if (ux != 0.f) {
      tx0 = (bx - px) / ux, tx1 = (bx + res - px) / ux;
      if (tx0 > tx1) std::swap(tx0, tx1);
    }
    if (uy != 0.f) {
      ty0 = (by - py) / uy, ty1 = (by + res - py) / uy;
      if (ty0 > ty1) std::swap(ty0, ty1);
    }
    const float tin = std::max(tx0, ty0), tout = std::min(tx1, ty1);
    float s = tin <= tout ? tin : (bx + 0.5f * res - px) * ux + (by + 0.5f * res - py) * uy;
    s = std::max(s, s0);
    if (s > s1) return h;
    h.s = s;
    h.cell_tri = cell[size_t(j) * nx + size_t(i)];
    if (tx0 >= ty0) h.nx = ux > 0 ? -1.f : 1.f;
    else h.ny = uy > 0 ? -1.f : 1.f;
    return h;
  }

  void cast(const HitBuffers& out, size_t idx, float px, float py, float dx, float dy, float t0,
            float t1, const CastOptions& opt) const {
    const float hz = std::sqrt(dx * dx + dy * dy);
    Hit h;
    if (t0 <= t1 && hz >= kMinHorizontal)
      h = walk(px, py, dx / hz, dy / hz, t0 * hz, t1 * hz, !opt.backface_is_solid);
    const uint32_t tri = h.cell_tri != kSolidCell ? h.cell_tri : kNoHit;
    writeHit(out, idx, h.s / hz, t1, tri, tri == kNoHit ? 0 : labels[tri], {h.nx, h.ny, 0.f}, opt);
  }
};

Grid2dCaster::Grid2dCaster(const Mesh& mesh, const Grid2dOptions& o)
    : PerRayCaster(o.threads), impl_(new Impl) {
  Impl& m = *impl_;
  if (!(o.resolution > 0)) throw std::invalid_argument("Grid2dCaster: resolution must be > 0");
  if (mesh.triangles.empty()) throw std::invalid_argument("Grid2dCaster: the map has no triangles");
  const Eigen::AlignedBox3f b = mesh.bounds();
  m.res = float(o.resolution);
  m.ox = b.min().x() - float(o.padding);
  m.oy = b.min().y() - float(o.padding);
  const double w = b.sizes().x() + 2 * o.padding, h = b.sizes().y() + 2 * o.padding;
  m.nx = size_t(std::ceil(w / o.resolution)) + 1;
  m.ny = size_t(std::ceil(h / o.resolution)) + 1;
  // 8 bytes per cell (triangle + clearance): past ~4 GB a typo in the resolution, not a map.
  if (double(m.nx) * double(m.ny) > 5e8)
    throw std::invalid_argument(fmt::format("Grid2dCaster: {} x {} cells at {} m ({:.1f} GB) is too large for "
                                            "this map; use a coarser resolution", m.nx, m.ny, o.resolution,
                                            double(m.nx) * double(m.ny) * 8e-9));
  m.cell.assign(m.nx * m.ny, kNoHit);
  m.labels = mesh.triangle_label;
  const std::vector<SliceSegment> segs = sliceMesh(mesh, float(o.height));
  m.rasterise(segs);
  if (o.fill_solids) m.fill(mesh, segs);
  m.finishBuild();
}

Grid2dCaster::Grid2dCaster(const OccupancyGrid& g, int threads)
    : PerRayCaster(threads), impl_(new Impl) {
  Impl& m = *impl_;
  if (std::abs(g.origin_yaw) > 1e-9) throw std::invalid_argument("Grid2dCaster: a rotated grid (origin yaw != 0)");
  if (!(g.resolution > 0) || g.width == 0 || g.height == 0 || g.cells.size() != g.width * g.height)
    throw std::invalid_argument("Grid2dCaster: empty or inconsistent grid");
  m.nx = g.width, m.ny = g.height, m.res = float(g.resolution);
  m.ox = float(g.origin_x), m.oy = float(g.origin_y);
  m.cell.resize(g.cells.size());
  for (size_t i = 0; i < g.cells.size(); ++i)
    m.cell[i] = g.cells[i] == OccupancyGrid::kOccupied ? kSolidCell : kNoHit;
  m.finishBuild();
}

Grid2dCaster::~Grid2dCaster() = default;

void Grid2dCaster::traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o,
                            const Eigen::Vector3f& d, float t0, float t1,
                            const CastOptions& opt) const {
  impl_->cast(out, i, o.x(), o.y(), d.x(), d.y(), t0, t1, opt);
}

size_t Grid2dCaster::width() const { return impl_->nx; }
size_t Grid2dCaster::height() const { return impl_->ny; }
double Grid2dCaster::resolution() const { return impl_->res; }
bool Grid2dCaster::occupied(size_t x, size_t y) const { return impl_->occ(long(x), long(y)); }
std::span<const float> Grid2dCaster::clearance() const { return impl_->clearance; }
double Grid2dCaster::originX() const { return impl_->ox; }
double Grid2dCaster::originY() const { return impl_->oy; }
size_t Grid2dCaster::memoryBytes() const {
  return impl_->cell.capacity() * sizeof(uint32_t) + impl_->clearance.capacity() * sizeof(float);
}

OccupancyGrid Grid2dCaster::grid() const {
  const Impl& m = *impl_;
  OccupancyGrid g;
  g.resize(m.nx, m.ny);
  g.resolution = m.res, g.origin_x = m.ox, g.origin_y = m.oy;
  for (size_t i = 0; i < m.cell.size(); ++i)
    g.cells[i] = m.cell[i] != kNoHit ? OccupancyGrid::kOccupied : OccupancyGrid::kFree;
  return g;
}

void Grid2dCaster::queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                             uint8_t* free) const {
  const Impl& m = *impl_;
  parallel(points.size(), 256, [&](size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) {
      const long x = long(std::floor((points[i].x() - m.ox) / m.res));
      const long y = long(std::floor((points[i].y() - m.oy) / m.res));
      // Outside the grid is farther than the padding from every surface.
      if (!(x >= 0 && y >= 0 && x < long(m.nx) && y < long(m.ny))) {
        free[i] = std::isfinite(points[i].x()) && std::isfinite(points[i].y());
        continue;
      }
      const size_t c = size_t(y) * m.nx + size_t(x);
      free[i] = m.cell[c] == kNoHit && m.clearance[c] >= clearance;
    }
  });
}

}  // namespace polyloc
