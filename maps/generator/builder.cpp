#include <polyloc/mapgen/builder.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace polyloc::mapgen {

namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

double signedArea(const std::vector<Eigen::Vector2f>& p) {
  double a = 0;
  for (size_t i = 0, n = p.size(); i < n; ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % n];
    a += double(u.x()) * v.y() - double(v.x()) * u.y();
  }
  return 0.5 * a;
}

// Inside or on the border: a vertex on an ear's edge must also block the ear.
bool inTriangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  constexpr double eps = -1e-12;
  return cross(a, b, p) >= eps && cross(b, c, p) >= eps && cross(c, a, p) >= eps;
}

// cos/sin with multiples of 90 degrees exact, so axis-aligned rooms keep exact coordinates.
void cosSin(float yaw, float& c, float& s) {
  const double quarter = yaw / (M_PI / 2);
  if (std::abs(quarter - std::round(quarter)) < 1e-9) {
    static constexpr float kc[4] = {1, 0, -1, 0}, ks[4] = {0, 1, 0, -1};
    const int q = ((static_cast<int>(std::lround(quarter)) % 4) + 4) % 4;
    c = kc[q];
    s = ks[q];
  } else {
    c = static_cast<float>(std::cos(double(yaw)));
    s = static_cast<float>(std::sin(double(yaw)));
  }
}

std::vector<Eigen::Vector2f> rectangle(const Eigen::Vector2f& lo, const Eigen::Vector2f& hi) {
  return {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
}

}  // namespace

std::vector<Triangle> triangulatePolygon(const std::vector<Eigen::Vector2f>& polygon) {
  const size_t n = polygon.size();
  if (n < 3) throw std::invalid_argument("triangulatePolygon: fewer than 3 points");
  std::vector<Vec2> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = polygon[i].cast<double>();
  std::vector<uint32_t> ring(n);
  std::iota(ring.begin(), ring.end(), 0u);
  if (signedArea(polygon) < 0) std::reverse(ring.begin(), ring.end());

  std::vector<Triangle> tris;
  tris.reserve(n - 2);
  while (ring.size() > 3) {
    bool clipped = false;
    const size_t m = ring.size();
    for (size_t i = 0; i < m && !clipped; ++i) {
      const uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (cross(p[a], p[b], p[c]) <= 1e-12) continue;  // reflex or collinear corner
      bool empty = true;
      for (uint32_t q : ring)
        if (q != a && q != b && q != c && inTriangle(p[q], p[a], p[b], p[c])) {
          empty = false;
          break;
        }
      if (!empty) continue;
      tris.push_back({a, b, c});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) throw std::invalid_argument("triangulatePolygon: polygon is not simple");
  }
  tris.push_back({ring[0], ring[1], ring[2]});
  return tris;
}

double signedVolume(const Mesh& mesh) {
  double v = 0;
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[t[2]].cast<double>();
    v += a.dot(b.cross(c));
  }
  return v / 6.0;
}

Eigen::Vector3f MeshBuilder::Frame::apply(const Eigen::Vector3f& p) const {
  return {origin.x() + c * p.x() - s * p.y(), origin.y() + s * p.x() + c * p.y(), z + p.z()};
}

void MeshBuilder::pushFrame(const Eigen::Vector2f& origin, float yaw, float z) {
  const Frame& parent = frames_.back();
  Frame f;
  const Eigen::Vector3f o = parent.apply({origin.x(), origin.y(), z});
  f.origin = o.head<2>();
  f.z = o.z();
  float c, s;
  cosSin(yaw, c, s);
  f.c = parent.c * c - parent.s * s;
  f.s = parent.s * c + parent.c * s;
  frames_.push_back(f);
}

void MeshBuilder::popFrame() {
  if (frames_.size() <= 1) throw std::logic_error("MeshBuilder::popFrame without pushFrame");
  frames_.pop_back();
}

void MeshBuilder::addSolid(const std::vector<Eigen::Vector3f>& vertices,
                           const std::vector<Triangle>& tris, const std::string& label) {
  Mesh solid;
  solid.vertices.reserve(vertices.size());
  for (const auto& v : vertices) solid.vertices.push_back(frames_.back().apply(v));
  solid.triangles = tris;
  // A solid that comes out inward (or flat) is a bug in the caller's numbers, not in the data.
  if (!(signedVolume(solid) > 0))
    throw std::logic_error("MeshBuilder: solid '" + label + "' is empty or inside out");
  const uint32_t id = mesh_.labelId(label);
  const uint32_t base = static_cast<uint32_t>(mesh_.vertices.size());
  mesh_.vertices.insert(mesh_.vertices.end(), solid.vertices.begin(), solid.vertices.end());
  for (const Triangle& t : tris) {
    mesh_.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    mesh_.triangle_label.push_back(id);
  }
}

void MeshBuilder::extrude(const std::vector<Eigen::Vector2f>& polygon,
                          const Eigen::Vector3f& origin, const Eigen::Vector3f& e1,
                          const Eigen::Vector3f& e2, float w0, float w1,
                          const std::string& label) {
  if (!(w1 > w0)) throw std::invalid_argument("MeshBuilder::extrude: empty extent for " + label);
  // Counter-clockwise in (e1, e2), so the cap at w1 faces +e3 and side quads face outward.
  std::vector<Eigen::Vector2f> poly = polygon;
  if (signedArea(poly) < 0) std::reverse(poly.begin(), poly.end());
  const uint32_t n = static_cast<uint32_t>(poly.size());
  const Eigen::Vector3f e3 = e1.cross(e2);
  std::vector<Eigen::Vector3f> v;
  v.reserve(2 * n);
  for (const auto& p : poly) v.push_back(origin + p.x() * e1 + p.y() * e2 + w0 * e3);
  for (const auto& p : poly) v.push_back(origin + p.x() * e1 + p.y() * e2 + w1 * e3);

  std::vector<Triangle> tris;
  for (const Triangle& t : triangulatePolygon(poly)) {
    tris.push_back({t[0] + n, t[1] + n, t[2] + n});  // cap at w1, facing +e3
    tris.push_back({t[0], t[2], t[1]});              // cap at w0, facing -e3
  }
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    tris.push_back({i, j, j + n});
    tris.push_back({i, j + n, i + n});
  }
  addSolid(v, tris, label);
}

void MeshBuilder::prism(const std::vector<Eigen::Vector2f>& footprint, float z0, float z1,
                        const std::string& label) {
  extrude(footprint, Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY(),
          z0, z1, label);
}

void MeshBuilder::box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                      const std::string& label) {
  prism(rectangle(lo.head<2>(), hi.head<2>()), lo.z(), hi.z(), label);
}

void MeshBuilder::orientedBox(const Eigen::Vector2f& centre, const Eigen::Vector2f& size,
                              float yaw, float z0, float z1, const std::string& label) {
  pushFrame(centre, yaw);
  box({-size.x() / 2, -size.y() / 2, z0}, {size.x() / 2, size.y() / 2, z1}, label);
  popFrame();
}

void MeshBuilder::cylinder(const Eigen::Vector2f& centre, float radius, float z0, float z1,
                           int segments, const std::string& label) {
  if (segments < 3) throw std::invalid_argument("MeshBuilder::cylinder: fewer than 3 segments");
  std::vector<Eigen::Vector2f> ring;
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * M_PI * i / segments;
    ring.push_back(centre + radius * Eigen::Vector2f(float(std::cos(a)), float(std::sin(a))));
  }
  prism(ring, z0, z1, label);
}

void MeshBuilder::ramp(const Eigen::Vector2f& lo, const Eigen::Vector2f& hi, float z_base,
                       float z_low, float z_high, const std::string& label) {
  // Profile in the (x, z) plane, swept along y; e1 x e2 = x cross z = -y, so w = -y.
  std::vector<Eigen::Vector2f> profile{{lo.x(), z_base}, {hi.x(), z_base}, {hi.x(), z_high}};
  if (z_low > z_base) profile.push_back({lo.x(), z_low});
  extrude(profile, Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitZ(),
          -hi.y(), -lo.y(), label);
}

void MeshBuilder::stairs(float x0, float y0, float y1, float z_start, int steps, float rise,
                         float tread, float z_base, const std::string& label) {
  if (steps < 1) throw std::invalid_argument("MeshBuilder::stairs: no steps");
  std::vector<Eigen::Vector2f> profile{{x0, z_base}, {x0 + steps * tread, z_base}};
  for (int k = steps; k >= 1; --k) {
    const float top = z_start + k * rise;
    if (!(top > z_base)) throw std::invalid_argument("MeshBuilder::stairs: step below z_base");
    profile.push_back({x0 + k * tread, top});
    profile.push_back({x0 + (k - 1) * tread, top});
  }
  extrude(profile, Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitZ(),
          -y1, -y0, label);
}

void MeshBuilder::slabWithHole(const Eigen::Vector2f& lo, const Eigen::Vector2f& hi,
                               const Eigen::Vector2f& hole_lo, const Eigen::Vector2f& hole_hi,
                               float z0, float z1, const std::string& label) {
  if (!((hole_lo.array() > lo.array()).all() && (hole_hi.array() < hi.array()).all() &&
        (hole_lo.array() < hole_hi.array()).all() && z0 < z1))
    throw std::invalid_argument("MeshBuilder::slabWithHole: hole not strictly inside the slab");
  // Outer ring 0..3 and inner ring 4..7 (both counter-clockwise) at z0, the same +8 at z1. The
  // top between the rings is four convex trapezoids, one per side.
  const auto outer = rectangle(lo, hi), inner = rectangle(hole_lo, hole_hi);
  std::vector<Eigen::Vector3f> v;
  for (float z : {z0, z1}) {
    for (const auto& p : outer) v.push_back({p.x(), p.y(), z});
    for (const auto& p : inner) v.push_back({p.x(), p.y(), z});
  }
  std::vector<Triangle> tris;
  auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    tris.push_back({a, b, c});
    tris.push_back({a, c, d});
  };
  for (uint32_t i = 0; i < 4; ++i) {
    const uint32_t j = (i + 1) % 4;
    quad(8 + i, 8 + j, 12 + j, 12 + i);  // top, facing +z
    quad(i, 4 + i, 4 + j, j);            // bottom, facing -z
    quad(i, j, 8 + j, 8 + i);            // outer side, facing out
    quad(4 + i, 12 + i, 12 + j, 4 + j);  // hole side, facing into the hole
  }
  addSolid(v, tris, label);
}

}  // namespace polyloc::mapgen
