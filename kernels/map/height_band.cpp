#include <polyloc/map/height_band.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

using V3 = Eigen::Vector3d;
constexpr size_t kMaxCells = 20000;   // per axis
constexpr size_t kBlockRows = 8;      // rows per task: a task owns its rows' cells
constexpr double kEdgeTolerance = 1e-6;  // m: a centre this close to a floor triangle is on it
// The winding number is taken at the cell centre moved by this much: off the edges of
// axis-aligned geometry that happen to pass through a centre (a vertical line through an edge
// would count both triangles, or neither).
constexpr double kProbeDx = 1.7320508e-5, kProbeDy = 2.2360680e-5;

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void checkOptions(const HeightBandOptions& o) {
  const auto bad = [](const char* option, double v, const char* rule) {
    throw std::invalid_argument("height band: " + std::string(option) + " = " + num(v) + ": " + rule);
  };
  if (!std::isfinite(o.resolution) || !(o.resolution > 0) || o.resolution > 1)
    bad("resolution", o.resolution, "must be a finite number in (0, 1] m");
  if (!std::isfinite(o.clearance) || o.clearance < 0) bad("clearance", o.clearance, "must be a finite number >= 0 m");
  if (!std::isfinite(o.height) || !(o.height > o.clearance))
    bad("height", o.height, ("must be a finite number > clearance (" + num(o.clearance) + " m)").c_str());
  if (!std::isfinite(o.padding) || o.padding < 0 || o.padding > 1e4) bad("padding", o.padding, "must be a finite number in [0, 1e4] m");
  if (!std::isfinite(o.max_floor_slope_deg) || o.max_floor_slope_deg < 0 || o.max_floor_slope_deg >= 90)
    bad("max_floor_slope_deg", o.max_floor_slope_deg, "must be a finite number in [0, 90) deg");
  if (o.floor_labels.empty()) throw std::invalid_argument("height band: floor_labels is empty: name the labels the robot drives on");
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + (x.empty() ? std::string("(unlabelled)") : x);
  return s;
}

// The mesh's labels with their triangle counts, for messages.
std::string labelCounts(const Mesh& m) {
  std::vector<size_t> n(m.label_names.size(), 0);
  for (uint32_t l : m.triangle_label)
    if (l < n.size()) ++n[l];
  std::string s;
  for (size_t l = 0; l < n.size(); ++l)
    if (n[l]) s += (s.empty() ? "" : ", ") + (m.label_names[l].empty() ? std::string("(unlabelled)") : m.label_names[l]) + " (" + std::to_string(n[l]) + ")";
  return s.empty() ? "none (no triangles)" : s;
}

// A convex polygon in 3D, clipped by vertical planes (x or y = const): at most 3 + 4 corners.
struct Poly {
  std::array<V3, 8> p;
  int n = 0;
};

// Keeps the part with p[axis] >= v (keep_above) or <= v; points on the plane are kept.
Poly clip(const Poly& in, int axis, double v, bool keep_above) {
  Poly out;
  if (in.n == 0) return out;
  const auto inside = [&](const V3& q) { return keep_above ? q[axis] >= v : q[axis] <= v; };
  for (int i = 0; i < in.n; ++i) {
    const V3& a = in.p[size_t(i)];
    const V3& b = in.p[size_t((i + 1) % in.n)];
    const bool ia = inside(a), ib = inside(b);
    if (ia && out.n < 8) out.p[size_t(out.n++)] = a;
    if (ia != ib && out.n < 8) {
      const double t = (v - a[axis]) / (b[axis] - a[axis]);
      V3 q = a + t * (b - a);
      q[axis] = v;
      out.p[size_t(out.n++)] = q;
    }
  }
  return out;
}

enum TriKind : uint8_t { kWalkable = 1, kObstacle = 2, kDanger = 4 };

struct Setup {
  const Mesh& mesh;
  const HeightBandOptions& o;
  size_t nx, ny;
  double ox, oy, r;
  Eigen::AlignedBox2d bounds;  // the mesh's x/y
  std::vector<uint8_t> kind;   // TriKind bits per triangle
  std::vector<int8_t> facing;  // +1 up, -1 down, 0 vertical (seen from above)
};

// Cells of one block of rows [j0, j1). All arrays are the whole grid's; only these rows are written.
struct Block {
  size_t j0, j1;
  const std::vector<uint32_t>* tris;
};

void runBlock(const Setup& s, const Block& b, std::vector<float>& floor_z, std::vector<uint8_t>& band_hit,
              std::vector<int16_t>& wind_above, std::vector<int16_t>& wind_total,
              std::vector<uint8_t>& danger) {
  const Mesh& m = s.mesh;
  const double r = s.r;
  const auto tri = [&](uint32_t t) {
    const Triangle& T = m.triangles[t];
    return std::array<V3, 3>{m.vertices[T[0]].cast<double>(), m.vertices[T[1]].cast<double>(), m.vertices[T[2]].cast<double>()};
  };
  const auto rowsOf = [&](double lo, double hi, double off) {  // rows whose (centre + off) lies in [lo, hi]
    const double a = std::ceil((lo - s.oy - off) / r - 0.5), c = std::floor((hi - s.oy - off) / r - 0.5);
    return std::pair<size_t, size_t>{size_t(std::clamp(a, double(b.j0), double(b.j1))),
                                     size_t(std::clamp(c + 1, double(b.j0), double(b.j1)))};
  };
  const auto colsOf = [&](double lo, double hi, double off) {
    const double a = std::ceil((lo - s.ox - off) / r - 0.5), c = std::floor((hi - s.ox - off) / r - 0.5);
    return std::pair<size_t, size_t>{size_t(std::clamp(a, 0.0, double(s.nx))), size_t(std::clamp(c + 1, 0.0, double(s.nx)))};
  };

  // 1. Floor: the highest walkable surface at each cell centre.
  for (uint32_t t : *b.tris) {
    if (!(s.kind[t] & kWalkable)) continue;
    const auto v = tri(t);
    const double xlo = std::min({v[0].x(), v[1].x(), v[2].x()}) - kEdgeTolerance, xhi = std::max({v[0].x(), v[1].x(), v[2].x()}) + kEdgeTolerance;
    const double ylo = std::min({v[0].y(), v[1].y(), v[2].y()}) - kEdgeTolerance, yhi = std::max({v[0].y(), v[1].y(), v[2].y()}) + kEdgeTolerance;
    const auto [ra, rb] = rowsOf(ylo, yhi, 0);
    const auto [ca, cb] = colsOf(xlo, xhi, 0);
    const V3 n = (v[1] - v[0]).cross(v[2] - v[0]);  // n.z > 0: walkable faces up
    std::array<Eigen::Vector2d, 3> e;
    std::array<double, 3> len;
    for (int k = 0; k < 3; ++k) {
      e[size_t(k)] = (v[size_t((k + 1) % 3)] - v[size_t(k)]).head<2>();
      len[size_t(k)] = e[size_t(k)].norm();
    }
    for (size_t j = ra; j < rb; ++j) {
      const double y = s.oy + (double(j) + 0.5) * r;
      for (size_t i = ca; i < cb; ++i) {
        const double x = s.ox + (double(i) + 0.5) * r;
        bool in = true;
        for (int k = 0; k < 3 && in; ++k) {
          const Eigen::Vector2d d = Eigen::Vector2d(x, y) - v[size_t(k)].head<2>();
          const double c = e[size_t(k)].x() * d.y() - e[size_t(k)].y() * d.x();
          in = c >= -kEdgeTolerance * len[size_t(k)];
        }
        if (!in) continue;
        const float z = float(v[0].z() - (n.x() * (x - v[0].x()) + n.y() * (y - v[0].y())) / n.z());
        float& f = floor_z[j * s.nx + i];
        if (!(f >= z)) f = z;  // NaN (none yet) or lower
      }
    }
  }

  // 2. Every triangle: winding number at the (moved) centres; obstacles and danger over the squares.
  const double c = s.o.clearance, h = s.o.height;
  for (uint32_t t : *b.tris) {
    const auto v = tri(t);
    const double xlo = std::min({v[0].x(), v[1].x(), v[2].x()}), xhi = std::max({v[0].x(), v[1].x(), v[2].x()});
    const double ylo = std::min({v[0].y(), v[1].y(), v[2].y()}), yhi = std::max({v[0].y(), v[1].y(), v[2].y()});
    if (s.facing[t] != 0) {
      const auto [ra, rb] = rowsOf(ylo, yhi, kProbeDy);
      const auto [ca, cb] = colsOf(xlo, xhi, kProbeDx);
      const Eigen::Vector2d a = v[0].head<2>(), e1 = v[1].head<2>() - a, e2 = v[2].head<2>() - a;
      const double det = e1.x() * e2.y() - e1.y() * e2.x();
      for (size_t j = ra; j < rb; ++j)
        for (size_t i = ca; i < cb; ++i) {
          const Eigen::Vector2d d = Eigen::Vector2d(s.ox + (double(i) + 0.5) * r + kProbeDx, s.oy + (double(j) + 0.5) * r + kProbeDy) - a;
          const double u = (d.x() * e2.y() - d.y() * e2.x()) / det, w = (e1.x() * d.y() - e1.y() * d.x()) / det;
          if (u < 0 || w < 0 || u + w > 1) continue;
          const size_t cell = j * s.nx + i;
          wind_total[cell] = int16_t(wind_total[cell] + s.facing[t]);
          const double z = v[0].z() + u * (v[1].z() - v[0].z()) + w * (v[2].z() - v[0].z());
          const float f = floor_z[cell];
          if (!std::isnan(f) && z > double(f) + c) wind_above[cell] = int16_t(wind_above[cell] + s.facing[t]);
        }
    }
    // Conservative: the triangle's part over each cell square, edges included.
    Poly whole;
    whole.n = 3;
    whole.p = {v[0], v[1], v[2]};
    const double yb0 = s.oy + double(b.j0) * r, yb1 = s.oy + double(b.j1) * r;
    if (yhi < yb0 || ylo > yb1) continue;
    const size_t ra = size_t(std::clamp(std::ceil((ylo - s.oy) / r) - 1, double(b.j0), double(b.j1)));
    const size_t rb = size_t(std::clamp(std::floor((yhi - s.oy) / r) + 1, double(b.j0), double(b.j1)));
    const bool walkable = s.kind[t] & kWalkable;
    for (size_t j = ra; j < rb; ++j) {
      const double y0 = s.oy + double(j) * r;
      const Poly row = clip(clip(whole, 1, y0, true), 1, y0 + r, false);
      if (row.n == 0) continue;
      double rxlo = row.p[0].x(), rxhi = rxlo;
      for (int k = 1; k < row.n; ++k) rxlo = std::min(rxlo, row.p[size_t(k)].x()), rxhi = std::max(rxhi, row.p[size_t(k)].x());
      const size_t ia = size_t(std::clamp(std::ceil((rxlo - s.ox) / r) - 1, 0.0, double(s.nx)));
      const size_t ib = size_t(std::clamp(std::floor((rxhi - s.ox) / r) + 1, 0.0, double(s.nx)));
      for (size_t i = ia; i < ib; ++i) {
        const double x0 = s.ox + double(i) * r;
        const Poly q = clip(clip(row, 0, x0, true), 0, x0 + r, false);
        if (q.n == 0) continue;
        const size_t cell = j * s.nx + i;
        if (s.kind[t] & kDanger) danger[cell] = 1;
        const float f = floor_z[cell];
        if (std::isnan(f) || band_hit[cell]) continue;
        double zlo = q.p[0].z(), zhi = zlo;
        for (int k = 1; k < q.n; ++k) zlo = std::min(zlo, q.p[size_t(k)].z()), zhi = std::max(zhi, q.p[size_t(k)].z());
        const double lo = double(f) + c, hi = double(f) + h;
        // A walkable surface counts where all of it lies in the band (a step up), not where it
        // only slopes across it (a ramp at a coarse resolution).
        if (walkable ? (zlo >= lo && zlo <= hi) : (zhi >= lo && zlo <= hi)) band_hit[cell] = 1;
      }
    }
  }
}

}  // namespace

HeightBand heightBandGrid(const Mesh& mesh, const HeightBandOptions& o, HeightBandStats* stats) {
  checkOptions(o);
  for (size_t k = 0; k < mesh.vertices.size(); ++k)
    if (!mesh.vertices[k].allFinite())
      throw std::invalid_argument("height band: mesh " + mesh.source + ": vertex " + std::to_string(k) + " is not finite");
  if (mesh.triangle_label.size() != mesh.triangles.size())
    throw std::invalid_argument("height band: mesh " + mesh.source + ": " + std::to_string(mesh.triangles.size()) + " triangles but " +
                                std::to_string(mesh.triangle_label.size()) + " labels");

  const auto ids = [&](const std::vector<std::string>& names) {
    std::vector<bool> is(mesh.label_names.size(), false);
    for (const auto& n : names)
      if (const int64_t id = mesh.findLabel(n); id >= 0 && size_t(id) < is.size()) is[size_t(id)] = true;
    return is;
  };
  const std::vector<bool> floor_label = ids(o.floor_labels), danger_label = ids(o.danger_labels);
  const double cos_slope = std::cos(o.max_floor_slope_deg * std::numbers::pi / 180.0);

  HeightBandStats st;
  st.triangles = mesh.numTriangles();
  std::vector<uint8_t> kind(mesh.numTriangles(), 0);
  std::vector<int8_t> facing(mesh.numTriangles(), 0);
  Eigen::AlignedBox2d bounds;
  for (const auto& v : mesh.vertices) bounds.extend(v.head<2>().cast<double>());
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    const Triangle& T = mesh.triangles[t];
    for (uint32_t k : T)
      if (k >= mesh.vertices.size())
        throw std::invalid_argument("height band: mesh " + mesh.source + ": triangle " + std::to_string(t) + " names vertex " +
                                    std::to_string(k) + " of " + std::to_string(mesh.vertices.size()));
    const V3 a = mesh.vertices[T[0]].cast<double>(), b = mesh.vertices[T[1]].cast<double>(), c = mesh.vertices[T[2]].cast<double>();
    const V3 n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0)) continue;  // degenerate: covers nothing
    const uint32_t l = mesh.triangle_label[t];
    const bool is_floor = l < floor_label.size() && floor_label[l];
    // Seen from above the triangle covers an area (a vertical one only a line).
    const double area_xy = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    facing[t] = int8_t(std::abs(area_xy) <= 1e-9 * len ? 0 : area_xy > 0 ? 1 : -1);
    if (is_floor && n.z() / len >= cos_slope && facing[t] > 0) {
      kind[t] |= kWalkable;
      ++st.floor_triangles;
    } else {
      kind[t] |= kObstacle;
    }
    if (l < danger_label.size() && danger_label[l]) {
      kind[t] |= kDanger;
      ++st.danger_triangles;
    }
  }
  if (st.floor_triangles == 0)
    throw std::runtime_error("height band: mesh " + (mesh.source.empty() ? std::string("(unnamed)") : mesh.source) +
                             " has no walkable floor: no triangle labelled " + joined(o.floor_labels) + " faces up within " +
                             num(o.max_floor_slope_deg) + " deg of level; its labels: " + labelCounts(mesh));

  const double r = o.resolution;
  // The origin on a multiple of the resolution (cells of two maps line up; round numbers in the YAML).
  const double ox = r * std::floor((bounds.min().x() - o.padding) / r + 1e-6), oy = r * std::floor((bounds.min().y() - o.padding) / r + 1e-6);
  const double wx = std::ceil((bounds.max().x() + o.padding - ox) / r - 1e-9), wy = std::ceil((bounds.max().y() + o.padding - oy) / r - 1e-9);
  if (wx > double(kMaxCells) || wy > double(kMaxCells))
    throw std::runtime_error("height band: the grid would be " + num(wx) + " x " + num(wy) + " cells (at most " +
                             std::to_string(kMaxCells) + " x " + std::to_string(kMaxCells) + "): the mesh spans " +
                             num(bounds.sizes().x()) + " x " + num(bounds.sizes().y()) + " m at resolution " + num(r) +
                             " m; choose a coarser resolution");
  const size_t nx = std::max<size_t>(1, size_t(wx)), ny = std::max<size_t>(1, size_t(wy));
  Setup s{mesh, o, nx, ny, ox, oy, r, bounds, std::move(kind), std::move(facing)};

  // Triangles binned by blocks of rows (every row a triangle's square-overlap can reach).
  const size_t blocks = (ny + kBlockRows - 1) / kBlockRows;
  std::vector<std::vector<uint32_t>> bins(blocks);
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    if (!s.kind[t]) continue;
    const Triangle& T = mesh.triangles[t];
    const double ylo = std::min({mesh.vertices[T[0]].y(), mesh.vertices[T[1]].y(), mesh.vertices[T[2]].y()});
    const double yhi = std::max({mesh.vertices[T[0]].y(), mesh.vertices[T[1]].y(), mesh.vertices[T[2]].y()});
    const double j0 = std::clamp(std::floor((ylo - oy) / r) - 1, 0.0, double(ny - 1));
    const double j1 = std::clamp(std::floor((yhi - oy) / r) + 1, 0.0, double(ny - 1));
    for (size_t k = size_t(j0) / kBlockRows; k <= size_t(j1) / kBlockRows; ++k) bins[k].push_back(uint32_t(t));
  }

  const size_t cells = nx * ny;
  HeightBand out;
  out.floor_z.assign(cells, std::numeric_limits<float>::quiet_NaN());
  out.danger.assign(cells, 0);
  std::vector<uint8_t> band_hit(cells, 0);
  std::vector<int16_t> wind_above(cells, 0), wind_total(cells, 0);
  tbb::parallel_for(size_t(0), blocks, [&](size_t k) {
    const Block b{k * kBlockRows, std::min(ny, (k + 1) * kBlockRows), &bins[k]};
    runBlock(s, b, out.floor_z, band_hit, wind_above, wind_total, out.danger);
  });

  // Drops: a cell whose floor lies higher than a neighbour's by more than the clearance (and the
  // slope allowed over one cell) is the edge of a platform, a ramp's side seen from the top. The
  // band rule marks such a step on its low side only where the step's face lies in the low cell;
  // this marks it on the high side whichever cell holds the face. Floors at the same height
  // (abutting slabs, tiles) make no edge. Each cell decides for itself: no races.
  const double step = o.clearance + r * std::tan(o.max_floor_slope_deg * std::numbers::pi / 180.0);
  std::vector<uint8_t> drop(cells, 0);
  tbb::parallel_for(size_t(0), ny, [&](size_t j) {
    for (size_t i = 0; i < nx; ++i) {
      const float f = out.floor_z[j * nx + i];
      if (std::isnan(f)) continue;
      const auto lower = [&](size_t ii, size_t jj) { return double(f) - double(out.floor_z[jj * nx + ii]) > step; };  // NaN: false
      drop[j * nx + i] = (i > 0 && lower(i - 1, j)) || (i + 1 < nx && lower(i + 1, j)) || (j > 0 && lower(i, j - 1)) ||
                         (j + 1 < ny && lower(i, j + 1));
    }
  });

  OccupancyGrid& g = out.grid;
  g.resize(nx, ny, OccupancyGrid::kFree);
  g.resolution = r;
  g.origin_x = ox, g.origin_y = oy, g.origin_yaw = 0;
  for (size_t j = 0; j < ny; ++j)
    for (size_t i = 0; i < nx; ++i) {
      const size_t cell = j * nx + i;
      int8_t& v = g.cells[cell];
      if (std::isnan(out.floor_z[cell])) {
        ++st.cells_no_floor;
        const Eigen::Vector2d centre(ox + (double(i) + 0.5) * r, oy + (double(j) + 0.5) * r);
        v = bounds.contains(centre) ? OccupancyGrid::kOccupied : OccupancyGrid::kUnknown;
      } else {
        const bool closed = wind_total[cell] == 0;
        if (!closed) ++st.open_columns;
        if (band_hit[cell]) v = OccupancyGrid::kOccupied;
        else if (closed && wind_above[cell] > 0) v = OccupancyGrid::kOccupied, ++st.cells_in_solid;
        else if (drop[cell]) v = OccupancyGrid::kOccupied, ++st.cells_drop;
      }
      if (v == OccupancyGrid::kOccupied) ++st.cells_occupied;
      else if (v == OccupancyGrid::kFree) ++st.cells_free;
      else ++st.cells_unknown;
      st.cells_danger += out.danger[cell];
    }
  if (stats) *stats = st;
  return out;
}

std::vector<std::string> saveHeightBand(const HeightBand& band, const std::string& yaml_path) {
  saveGridMap(band.grid, yaml_path);
  std::vector<std::string> written{yaml_path};
  if (std::find(band.danger.begin(), band.danger.end(), uint8_t{1}) == band.danger.end()) return written;
  OccupancyGrid mask = band.grid;
  for (size_t k = 0; k < mask.cells.size(); ++k) mask.cells[k] = band.danger[k] ? OccupancyGrid::kOccupied : OccupancyGrid::kFree;
  const std::filesystem::path p(yaml_path);
  written.push_back((p.parent_path() / (p.stem().string() + ".danger.yaml")).string());
  saveGridMap(mask, written.back());
  return written;
}

}  // namespace polyloc
