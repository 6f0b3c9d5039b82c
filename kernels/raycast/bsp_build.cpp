// BSP build step 3: the solid-leaf tree. Work items on an explicit stack (no recursion); each
// node takes the candidate plane with the lowest k * splits + (1 - k) * |front - back|, consumes
// the polygons on it, and sends the rest to its sides. A side with no polygon left is a leaf:
// empty in front (outside the faces that bound it), solid behind.
#include "bsp_tree.hpp"

#include <polyloc/map/load.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc::bsp {
namespace {

struct Work {
  std::vector<Polygon> polys;
  int32_t parent;  // -1 for the root
  int side;        // 0 front, 1 back of the parent
  int depth;
};

struct Choice {
  uint32_t plane = 0;
  bool reversed = false;
};

// Scores the distinct planes of `polys` (every one, or an evenly spaced sample).
Choice choosePlane(const std::vector<Polygon>& polys, const PlaneSet& planes,
                   const BspOptions& opt, std::vector<uint32_t>& stamp, uint32_t node_id) {
  std::vector<Choice> cands;
  for (const Polygon& p : polys)
    if (stamp[p.plane] != node_id) {
      stamp[p.plane] = node_id;
      cands.push_back({p.plane, p.reversed});
    }
  if (opt.max_candidates > 0 && cands.size() > opt.max_candidates) {
    std::vector<Choice> sample(opt.max_candidates);
    for (size_t i = 0; i < sample.size(); ++i) sample[i] = cands[i * cands.size() / sample.size()];
    cands.swap(sample);
  }
  if (cands.size() == 1) return cands[0];
  Choice best = cands[0];
  double best_score = std::numeric_limits<double>::infinity();
  for (const Choice& c : cands) {
    const Plane& pl = planes[c.plane];
    long splits = 0, front = 0, back = 0;
    for (const Polygon& p : polys) {
      if (p.plane == c.plane) continue;
      switch (classify(p, pl, opt.plane_eps)) {
        case kFront: ++front; break;
        case kBack: ++back; break;
        case kSpanning: ++splits; ++front; ++back; break;
        case kOn: break;
      }
    }
    const double score = opt.k * double(splits) + (1.0 - opt.k) * double(std::labs(front - back));
    if (score < best_score) {
      best_score = score;
      best = c;
    }
  }
  return best;
}

}  // namespace

std::vector<BuildNode> buildNodes(std::vector<Polygon> polys, const PlaneSet& planes,
                                  const BspOptions& opt, BspStats& stats, int32_t& root) {
  std::vector<BuildNode> nodes;
  root = kEmpty;
  if (polys.empty()) return nodes;
  std::vector<uint32_t> stamp(planes.size(), UINT32_MAX);
  std::vector<Work> stack;
  stack.push_back({std::move(polys), -1, 0, 1});
  Polygon f, b;
  while (!stack.empty()) {
    Work w = std::move(stack.back());
    stack.pop_back();
    if (w.depth > opt.max_depth)
      throw MapError(fmt::format("bsp: tree deeper than max_depth {} (raise BspOptions::max_depth)",
                                 opt.max_depth));
    stats.depth = std::max(stats.depth, w.depth);
    const int32_t id = static_cast<int32_t>(nodes.size());
    const Choice c = choosePlane(w.polys, planes, opt, stamp, static_cast<uint32_t>(id));
    const Plane split_plane = planes.oriented(c.plane, c.reversed);
    BuildNode node;
    node.plane = c.plane;
    node.reversed = c.reversed;
    std::vector<Polygon> front, back;
    for (Polygon& p : w.polys) {
      const Side s = p.plane == c.plane ? kOn : classify(p, split_plane, opt.plane_eps);
      if (s == kOn) {
        node.tris.push_back(p.tri);
      } else if (s == kFront) {
        front.push_back(std::move(p));
      } else if (s == kBack) {
        back.push_back(std::move(p));
      } else {
        split(p, split_plane, opt.plane_eps, f, b);
        ++stats.split_polygons;
        if (!f.v.empty()) front.push_back(f);
        if (!b.v.empty()) back.push_back(b);
      }
    }
    std::sort(node.tris.begin(), node.tris.end());
    node.tris.erase(std::unique(node.tris.begin(), node.tris.end()), node.tris.end());
    w.polys.clear();
    w.polys.shrink_to_fit();
    if (w.parent < 0)
      root = id;
    else
      nodes[w.parent].child[w.side] = id;
    nodes.push_back(std::move(node));
    if (front.empty())
      ++stats.empty_leaves;
    else
      stack.push_back({std::move(front), id, 0, w.depth + 1});
    if (back.empty())
      ++stats.solid_leaves;
    else
      stack.push_back({std::move(back), id, 1, w.depth + 1});
  }
  stats.nodes = nodes.size();
  return nodes;
}

Tree compact(const std::vector<BuildNode>& nodes, int32_t root, const PlaneSet& planes) {
  Tree t;
  t.root = root;
  t.nodes.reserve(nodes.size());
  for (const BuildNode& b : nodes) {
    const Plane p = planes.oriented(b.plane, b.reversed);
    Node n;
    n.nx = static_cast<float>(p.n.x());
    n.ny = static_cast<float>(p.n.y());
    n.nz = static_cast<float>(p.n.z());
    n.d = static_cast<float>(p.d);
    n.child[0] = b.child[0];
    n.child[1] = b.child[1];
    n.tri_first = static_cast<uint32_t>(t.tris.size());
    n.tri_count = static_cast<uint32_t>(b.tris.size());
    t.tris.insert(t.tris.end(), b.tris.begin(), b.tris.end());
    t.nodes.push_back(n);
  }
  return t;
}

}  // namespace polyloc::bsp
