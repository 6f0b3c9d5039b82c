#include <polyloc/geometry/random.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/sim/chairs.hpp>
#include <polyloc/sim/world.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace polyloc {

namespace {

constexpr uint64_t kWallStream = 0x57414C4CULL;     // "WALL"
constexpr uint64_t kClutterStream = 0x434C5554ULL;  // "CLUT"
constexpr int kClutterTries = 200;                  // draws per box before giving up
constexpr float kProbeHeight = 2.0f;                // m, where clutter probes start

// The mesh without the given triangles (vertices kept: unused ones cost nothing to a caster).
Mesh withoutTriangles(const Mesh& m, const std::vector<uint32_t>& drop) {
  std::vector<char> gone(m.numTriangles(), 0);
  for (uint32_t t : drop) gone[t] = 1;
  Mesh out = m;
  out.triangles.clear();
  out.triangle_label.clear();
  for (size_t t = 0; t < m.numTriangles(); ++t)
    if (!gone[t]) out.triangles.push_back(m.triangles[t]), out.triangle_label.push_back(m.triangle_label[t]);
  return out;
}

// Every triangle split in four at its edge midpoints: the same surfaces, other triangles and
// edges (a map's tessellation is an accident of its modeller; the world's need not match it).
Mesh subdivided(const Mesh& m) {
  Mesh out;
  out.label_names = m.label_names;
  out.source = m.source;
  out.vertices = m.vertices;
  std::unordered_map<uint64_t, uint32_t> mid;  // shared edges keep shared midpoints: solids stay closed
  const auto midpoint = [&](uint32_t a, uint32_t b) {
    const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    auto [it, fresh] = mid.emplace(key, uint32_t(out.vertices.size()));
    if (fresh) out.vertices.push_back(0.5f * (m.vertices[a] + m.vertices[b]));
    return it->second;
  };
  for (size_t t = 0; t < m.numTriangles(); ++t) {
    const Triangle& tri = m.triangles[t];
    const uint32_t a = tri[0], b = tri[1], c = tri[2];
    const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    for (const Triangle& n : {Triangle{a, ab, ca}, Triangle{ab, b, bc}, Triangle{ca, bc, c}, Triangle{ab, bc, ca}}) {
      out.triangles.push_back(n);
      out.triangle_label.push_back(m.triangle_label[t]);
    }
  }
  return out;
}

double distanceToRoute(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& route) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < route.size(); ++i) {
    const Eigen::Vector2d a = route[i], b = i + 1 < route.size() ? route[i + 1] : route[i];
    const Eigen::Vector2d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + s * ab - p).norm());
  }
  return best;
}

// Clutter boxes on free floor: every corner and the centre of the footprint, looked at from
// above, must see the floor first (not a table, a wall top or a cabinet).
size_t addClutter(Mesh& mesh, const ClutterSpec& c, const CounterRng& rng,
                  const std::vector<Eigen::Vector2d>& route) {
  if (c.count <= 0) return 0;
  const int64_t floor_label = mesh.findLabel("floor");
  if (floor_label < 0) throw std::runtime_error("world.clutter: the map has no 'floor' to put clutter on");
  const EmbreeCaster caster(mesh);
  const Eigen::AlignedBox3f box = mesh.bounds();
  // Probes look down from 2 m above z = 0, the floor maps are built on: under a ceiling, above
  // tables and shelves.
  const float top = std::min(box.max().z() + 1.f, kProbeHeight);
  const uint32_t label = mesh.labelId(c.label);
  size_t placed = 0;
  for (uint64_t draw = 0; placed < size_t(c.count) && draw < uint64_t(c.count) * kClutterTries; ++draw) {
    const Eigen::Vector2d centre(rng.uniform(box.min().x(), box.max().x(), kClutterStream, draw, 0),
                                 rng.uniform(box.min().y(), box.max().y(), kClutterStream, draw, 1));
    const double sx = rng.uniform(c.size_min, c.size_max, kClutterStream, draw, 2);
    const double sy = rng.uniform(c.size_min, c.size_max, kClutterStream, draw, 3);
    const double h = rng.uniform(c.height_min, c.height_max, kClutterStream, draw, 4);
    const double yaw = rng.uniform(-M_PI, M_PI, kClutterStream, draw, 5);
    if (distanceToRoute(centre, route) < c.route_clearance + 0.5 * std::hypot(sx, sy)) continue;
    const Eigen::Rotation2Dd rot(yaw);
    float ox[5], oy[5], oz[5], dx[5], dy[5], dz[5], range[5];
    uint32_t lab[5];
    for (int k = 0; k < 5; ++k) {
      const Eigen::Vector2d corner = k == 4 ? Eigen::Vector2d::Zero() : Eigen::Vector2d((k & 1 ? 0.5 : -0.5) * sx, (k & 2 ? 0.5 : -0.5) * sy);
      const Eigen::Vector2d p = centre + rot * corner;
      ox[k] = float(p.x()), oy[k] = float(p.y()), oz[k] = top, dx[k] = 0, dy[k] = 0, dz[k] = -1;
    }
    caster.castRays({ox, oy, oz, dx, dy, dz, nullptr, nullptr, 5}, {range, nullptr, lab, nullptr, nullptr, nullptr});
    bool free = true;
    float ground = 0;
    for (int k = 0; k < 5 && free; ++k) {
      free = std::isfinite(range[k]) && lab[k] == uint32_t(floor_label);
      ground = std::max(ground, top - range[k]);
    }
    if (!free) continue;
    mesh.addBox({-0.5 * sx, -0.5 * sy, ground}, {0.5 * sx, 0.5 * sy, ground + h}, label, centre, yaw);
    ++placed;
  }
  if (placed < size_t(c.count)) {
    std::ostringstream os;
    os << "world.clutter: placed " << placed << " of " << c.count << " boxes (free floor " << c.route_clearance
       << " m away from the route is too scarce)";
    throw std::runtime_error(os.str());
  }
  return placed;
}

}  // namespace

Mesh buildWorld(const Mesh& base, const WorldSpec& spec, uint64_t seed,
                const std::vector<Eigen::Vector2d>& route, WorldChanges* changes) {
  WorldChanges ch;
  ch.triangles_before = base.numTriangles();
  Mesh world = base;
  const CounterRng rng(spec.seed ? *spec.seed : seed);

  std::vector<uint32_t> drop;
  for (const WorldRemove& r : spec.remove) {
    const std::vector<MeshObject> objects = findObjects(world, r.label);
    const MeshObject* best = nullptr;
    double best_d = 0.6;
    for (const MeshObject& o : objects)
      if (const double d = (o.centre() - r.at).norm(); d <= best_d) best = &o, best_d = d;
    if (!best) {
      std::ostringstream os;
      os << r.where << ": no '" << r.label << "' object within 0.6 m of (" << r.at.x() << ", " << r.at.y()
         << ") (the map has " << objects.size() << ")";
      throw std::runtime_error(os.str());
    }
    drop.insert(drop.end(), best->triangles.begin(), best->triangles.end());
    ++ch.removed;
  }
  if (!drop.empty()) world = withoutTriangles(world, drop);

  for (const WorldBox& b : spec.add) {
    const Eigen::Vector3d mid = 0.5 * (b.lo + b.hi);
    world.addBox(b.lo - Eigen::Vector3d(mid.x(), mid.y(), 0), b.hi - Eigen::Vector3d(mid.x(), mid.y(), 0),
                 world.labelId(b.label), mid.head<2>(), b.yaw);
    ++ch.added;
  }

  // Each solid (its own vertices) of an offset label moves as a whole, uniform in a disc: the
  // walls as built, each a few centimetres from where the plan has it.
  if (spec.wall_offset > 0) {
    for (const std::string& label : spec.offset_labels) {
      const std::vector<MeshObject> solids = findObjects(world, label, false);
      for (size_t i = 0; i < solids.size(); ++i) {
        const double r = spec.wall_offset * std::sqrt(rng.uniform(kWallStream, i, 0));
        const double a = rng.uniform(0, 2 * M_PI, kWallStream, i, 1);
        const Eigen::Vector3f shift(float(r * std::cos(a)), float(r * std::sin(a)), 0.f);
        std::unordered_map<uint32_t, uint32_t> remap;  // fresh vertices: other labels keep theirs
        for (uint32_t t : solids[i].triangles)
          for (uint32_t& v : world.triangles[t]) {
            auto [it, fresh] = remap.emplace(v, uint32_t(world.vertices.size()));
            if (fresh) world.vertices.push_back(world.vertices[v] + shift);
            v = it->second;
          }
        ++ch.shifted;
      }
    }
  }

  ch.clutter = addClutter(world, spec.clutter, rng, route);
  for (int k = 0; k < spec.subdivide; ++k) world = subdivided(world);
  ch.triangles_after = world.numTriangles();
  if (changes) *changes = ch;
  return world;
}

}  // namespace polyloc
