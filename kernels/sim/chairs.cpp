#include <polyloc/geometry/random.hpp>
#include <polyloc/sim/chairs.hpp>

#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace polyloc {

namespace {

constexpr uint64_t kChairStream = 0x4348414952ULL;  // "CHAIR"

struct UnionFind {
  std::vector<size_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  size_t find(size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(size_t a, size_t b) { parent[find(a)] = find(b); }
};

}  // namespace

std::vector<MeshObject> findObjects(const Mesh& mesh, const std::string& label, bool join_touching) {
  const int64_t id = mesh.findLabel(label);
  if (id < 0) return {};
  std::vector<uint32_t> tris;
  for (size_t t = 0; t < mesh.numTriangles(); ++t)
    if (mesh.triangle_label[t] == static_cast<uint32_t>(id)) tris.push_back(static_cast<uint32_t>(t));
  // Solids: triangles sharing a vertex.
  UnionFind uf(tris.size());
  std::unordered_map<uint32_t, size_t> first_use;
  for (size_t i = 0; i < tris.size(); ++i)
    for (uint32_t v : mesh.triangles[tris[i]]) {
      auto [it, fresh] = first_use.emplace(v, i);
      if (!fresh) uf.join(i, it->second);
    }
  std::unordered_map<size_t, size_t> solid_of;
  std::vector<Eigen::AlignedBox3f> boxes;
  std::vector<size_t> tri_solid(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) {
    auto [it, fresh] = solid_of.emplace(uf.find(i), boxes.size());
    if (fresh) boxes.emplace_back();
    tri_solid[i] = it->second;
    for (uint32_t v : mesh.triangles[tris[i]]) boxes[it->second].extend(mesh.vertices[v]);
  }
  // Objects: solids whose bounding boxes touch (1 cm tolerance).
  UnionFind objs(boxes.size());
  for (size_t a = 0; a < boxes.size() && join_touching; ++a)
    for (size_t b = a + 1; b < boxes.size(); ++b) {
      Eigen::AlignedBox3f ea = boxes[a];
      ea.min().array() -= 0.01f;
      ea.max().array() += 0.01f;
      if (ea.intersects(boxes[b])) objs.join(a, b);
    }
  std::unordered_map<size_t, size_t> object_of;
  std::vector<MeshObject> out;
  for (size_t i = 0; i < tris.size(); ++i) {
    auto [it, fresh] = object_of.emplace(objs.find(tri_solid[i]), out.size());
    if (fresh) out.emplace_back();
    MeshObject& o = out[it->second];
    o.triangles.push_back(tris[i]);
    for (uint32_t v : mesh.triangles[tris[i]]) o.bounds.extend(mesh.vertices[v]);
  }
  return out;
}

Mesh moveChairs(const Mesh& mesh, const ChairMoves& spec, uint64_t seed,
                std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>* moved) {
  if (spec.empty()) return mesh;
  const std::vector<MeshObject> chairs = findObjects(mesh, spec.label);
  // Per chair: translation of its centre and rotation about it.
  std::vector<Eigen::Vector2d> target(chairs.size());
  std::vector<double> turn(chairs.size(), 0.0);
  std::vector<bool> touched(chairs.size(), false);
  for (size_t c = 0; c < chairs.size(); ++c) target[c] = chairs[c].centre();
  for (const ChairMove& m : spec.moves) {
    size_t best = chairs.size();
    double best_d = 0.6;
    for (size_t c = 0; c < chairs.size(); ++c) {
      const double d = (chairs[c].centre() - m.from).norm();
      if (d <= best_d) best = c, best_d = d;
    }
    if (best == chairs.size()) {
      std::ostringstream os;
      os << m.where << ": no '" << spec.label << "' object within 0.6 m of (" << m.from.x() << ", "
         << m.from.y() << ") (the map has " << chairs.size() << ")";
      throw std::runtime_error(os.str());
    }
    target[best] = m.to, turn[best] += m.rotate, touched[best] = true;
  }
  const CounterRng rng(spec.seed ? *spec.seed : seed);
  if (spec.random_shift > 0 || spec.random_rotation > 0) {
    for (size_t c = 0; c < chairs.size(); ++c) {
      const double r = spec.random_shift * std::sqrt(rng.uniform(kChairStream, c, 0));
      const double a = rng.uniform(0, 2 * M_PI, kChairStream, c, 1);
      target[c] += Eigen::Vector2d(r * std::cos(a), r * std::sin(a));
      turn[c] += rng.uniform(-spec.random_rotation, spec.random_rotation, kChairStream, c, 2);
      touched[c] = true;
    }
  }
  Mesh out = mesh;
  for (size_t c = 0; c < chairs.size(); ++c) {
    if (!touched[c]) continue;
    const Eigen::Vector2d from = chairs[c].centre();
    const Eigen::Rotation2Dd rot(turn[c]);
    std::unordered_map<uint32_t, uint32_t> remap;  // fresh vertices: moved chairs share none
    for (uint32_t t : chairs[c].triangles)
      for (uint32_t& v : out.triangles[t]) {
        auto [it, fresh] = remap.emplace(v, static_cast<uint32_t>(out.vertices.size()));
        if (fresh) {
          const Eigen::Vector3f p = mesh.vertices[v];
          const Eigen::Vector2d q = target[c] + rot * (Eigen::Vector2d(p.x(), p.y()) - from);
          out.vertices.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()), p.z());
        }
        v = it->second;
      }
    if (moved) moved->push_back({from, target[c]});
  }
  return out;
}

}  // namespace polyloc
