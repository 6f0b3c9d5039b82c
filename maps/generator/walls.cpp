#include <polyloc/mapgen/walls.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace polyloc::mapgen {

namespace {

constexpr float kEps = 1e-4f;  // plans are in centimetres at best; this is "the same point"

std::string str(const Eigen::Vector2f& p) {
  return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")";
}

}  // namespace

void WallPlan::addWall(const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
  if (std::abs(a.y() - b.y()) < kEps && std::abs(a.x() - b.x()) > kEps)
    lines_.push_back({true, a.y(), std::min(a.x(), b.x()), std::max(a.x(), b.x()), true});
  else if (std::abs(a.x() - b.x()) < kEps && std::abs(a.y() - b.y()) > kEps)
    lines_.push_back({false, a.x(), std::min(a.y(), b.y()), std::max(a.y(), b.y()), true});
  else
    throw std::invalid_argument("WallPlan: wall " + str(a) + "-" + str(b) +
                                " is empty or not axis-aligned");
}

void WallPlan::addGuide(const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
  addWall(a, b);
  lines_.back().solid = false;
}

void WallPlan::addOpening(const Eigen::Vector2f& centre, float width, float height) {
  if (!(width > 0 && height > 0))
    throw std::invalid_argument("WallPlan: opening at " + str(centre) + " has no size");
  openings_.push_back({centre, width, height});
}

std::vector<WallPlan::Line> WallPlan::merged() const {
  std::vector<Line> sorted = lines_;
  std::sort(sorted.begin(), sorted.end(), [](const Line& a, const Line& b) {
    if (a.along_x != b.along_x) return a.along_x;
    if (a.solid != b.solid) return a.solid;
    if (a.coord != b.coord) return a.coord < b.coord;
    return a.lo < b.lo;
  });
  std::vector<Line> out;
  for (const Line& l : sorted) {
    if (!out.empty()) {
      Line& last = out.back();
      if (last.along_x == l.along_x && last.solid == l.solid &&
          std::abs(last.coord - l.coord) < kEps && l.lo <= last.hi + kEps) {
        last.hi = std::max(last.hi, l.hi);
        continue;
      }
    }
    out.push_back(l);
  }
  return out;
}

// Walls along x reach over the corner they share with a wall along y; walls along y and walls
// ending on another wall's middle (T) stop at the other wall's centre line, inside it.
float WallPlan::extension(const Line& wall, float end, const std::vector<Line>& all) const {
  if (!wall.along_x) return 0.f;
  for (const Line& p : all) {
    if (p.along_x || std::abs(p.coord - end) > kEps) continue;
    if (wall.coord < p.lo - kEps || wall.coord > p.hi + kEps) continue;
    if (std::abs(wall.coord - p.lo) < kEps || std::abs(wall.coord - p.hi) < kEps)
      return style_.thickness / 2;
  }
  return 0.f;
}

void WallPlan::build(MeshBuilder& builder) const {
  const std::vector<Line> lines = merged();
  const float t = style_.thickness, z0 = style_.z0, z1 = style_.z0 + style_.height;
  std::vector<bool> used(openings_.size(), false);

  for (const Line& wall : lines) {
    if (!wall.solid) continue;
    const float a = wall.lo - extension(wall, wall.lo, lines);
    const float b = wall.hi + extension(wall, wall.hi, lines);
    auto emit = [&](float u0, float u1, float za, float zb) {
      if (wall.along_x)
        builder.box({u0, wall.coord - t / 2, za}, {u1, wall.coord + t / 2, zb}, style_.label);
      else
        builder.box({wall.coord - t / 2, u0, za}, {wall.coord + t / 2, u1, zb}, style_.label);
    };

    std::vector<const Opening*> here;
    for (size_t i = 0; i < openings_.size(); ++i) {
      const Opening& o = openings_[i];
      const float across = wall.along_x ? o.centre.y() : o.centre.x();
      const float along = wall.along_x ? o.centre.x() : o.centre.y();
      if (std::abs(across - wall.coord) < kEps && along > a && along < b) {
        here.push_back(&o);
        used[i] = true;
      }
    }
    auto along = [&](const Opening* o) { return wall.along_x ? o->centre.x() : o->centre.y(); };
    std::sort(here.begin(), here.end(),
              [&](const Opening* x, const Opening* y) { return along(x) < along(y); });

    // Pieces of full height between the openings; each must keep some wall.
    constexpr float kMinPiece = 0.02f;
    std::vector<std::pair<float, float>> pieces;
    float start = a;
    for (const Opening* o : here) {
      const float u0 = along(o) - o->width / 2;
      if (u0 - start < kMinPiece)
        throw std::invalid_argument("WallPlan: opening at " + str(o->centre) +
                                    " does not fit in its wall");
      pieces.push_back({start, u0});
      start = u0 + o->width;
    }
    if (b - start < kMinPiece && !here.empty())
      throw std::invalid_argument("WallPlan: opening at " + str(here.back()->centre) +
                                  " does not fit in its wall");
    pieces.push_back({start, b});
    for (const auto& [u0, u1] : pieces) emit(u0, u1, z0, z1);

    for (size_t k = 0; k < here.size(); ++k) {
      const Opening* o = here[k];
      if (o->height >= style_.height) continue;
      const float left = std::min(style_.lintel_overlap, (pieces[k].second - pieces[k].first) / 3);
      const float right =
          std::min(style_.lintel_overlap, (pieces[k + 1].second - pieces[k + 1].first) / 3);
      const float u0 = along(o) - o->width / 2;
      emit(u0 - left, u0 + o->width + right, z0 + o->height, z1);
    }
  }
  for (size_t i = 0; i < openings_.size(); ++i)
    if (!used[i])
      throw std::invalid_argument("WallPlan: opening at " + str(openings_[i].centre) +
                                  " is on no wall");
}

}  // namespace polyloc::mapgen
