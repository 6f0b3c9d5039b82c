#include <polyloc/sim/body_collision.hpp>

#include <polyloc/geometry/closest_point.hpp>

#include <polyloc/sim/convex_overlap.hpp>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace polyloc {

namespace {

constexpr double kMaxCoord = 1e6;     // m: a pose beyond this is a bug upstream
constexpr long kMaxCells = 1L << 24;  // a huge map gets coarser cells, not gigabytes of grid
constexpr long kMaxCellsPerAxis = 1L << 16;

bool insidePolygon(const std::vector<Eigen::Vector2d>& ccw, const Eigen::Vector2d& p) {
  for (size_t i = 0; i < ccw.size(); ++i) {
    const Eigen::Vector2d e = ccw[(i + 1) % ccw.size()] - ccw[i], d = p - ccw[i];
    if (e.x() * d.y() - e.y() * d.x() < 0) return false;
  }
  return true;
}

}  // namespace

BodyCollider::BodyCollider(const Mesh& world, const RobotSpec& body, double floor_clearance)
    : mesh_(world), z0_(floor_clearance), z1_(body.height) {
  if (!std::isfinite(body.height) || !std::isfinite(floor_clearance) || floor_clearance < 0 ||
      floor_clearance >= body.height)
    throw std::invalid_argument(
        fmt::format("floor_clearance {} must lie in [0, robot height {})", floor_clearance, body.height));
  std::vector<Eigen::Vector2d> outline = body.footprint;
  if (outline.empty())
    for (int i = 0; i < 16; ++i)
      outline.emplace_back(body.radius * std::cos(M_PI / 8 * i), body.radius * std::sin(M_PI / 8 * i));
  pieces_ = convexPieces(outline);

  // Broad phase over the finite triangles (a non-finite vertex can touch nothing).
  std::vector<Eigen::AlignedBox3d> tb(mesh_.numTriangles());
  Eigen::AlignedBox3d all;
  for (uint32_t t = 0; t < tb.size(); ++t) {
    for (int k = 0; k < 3; ++k) tb[t].extend(vertex(t, k));
    if (tb[t].min().allFinite() && tb[t].max().allFinite()) all.extend(tb[t]);
    else tb[t].setEmpty();
  }
  if (all.isEmpty()) return;
  const double w = all.sizes().x(), h = all.sizes().y();
  cell_ = std::max({cell_, std::sqrt(w * h / double(kMaxCells)) * 1.01, std::max(w, h) / double(kMaxCellsPerAxis)});
  gx_ = all.min().x(), gy_ = all.min().y();
  nx_ = std::max(1L, long(std::ceil(w / cell_))), ny_ = std::max(1L, long(std::ceil(h / cell_)));
  cell_start_.assign(size_t(nx_ * ny_) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {  // count, then fill
    std::vector<size_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (uint32_t t = 0; t < tb.size(); ++t) {
      if (tb[t].isEmpty()) continue;
      const auto [i0, i1, j0, j1] = cellRange(tb[t]);
      for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i) {
          const size_t c = size_t(j * nx_ + i);
          if (pass == 0) ++cell_start_[c + 1];
          else entries_[fill[c]++] = {t, float(tb[t].min().z()), float(tb[t].max().z())};
        }
    }
    if (pass == 0) {
      for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
      entries_.resize(cell_start_.back());
    }
  }
}

std::array<long, 4> BodyCollider::cellRange(const Eigen::AlignedBox3d& b) const {
  auto index = [&](double v, double origin, long n) {
    return std::clamp(long(std::floor((v - origin) / cell_)), 0L, n - 1);
  };
  return {index(b.min().x(), gx_, nx_), index(b.max().x(), gx_, nx_), index(b.min().y(), gy_, ny_),
          index(b.max().y(), gy_, ny_)};
}

BodyContact BodyCollider::check(const Pose& map_T_base, const PeopleScene* people) const {
  const double x = map_T_base.x(), y = map_T_base.y(), z = map_T_base.z(), yaw = map_T_base.yaw();
  for (double v : {x, y, z})
    if (!std::isfinite(v) || std::abs(v) > kMaxCoord)
      throw std::invalid_argument(
          fmt::format("BodyCollider: pose x, y, z = ({}, {}, {}): not finite or beyond 1e6 m", x, y, z));
  if (!std::isfinite(yaw)) throw std::invalid_argument("BodyCollider: pose rotation is not finite");

  const double z0 = z + z0_, z1 = z + z1_;
  std::vector<ConvexShape> parts;
  Eigen::AlignedBox3d bb;
  for (const auto& piece : pieces_) {
    parts.push_back(ConvexShape::prism(piece, z0, z1, {x, y}, yaw));
    for (const auto& v : parts.back().vertices) bb.extend(v);
  }
  const Eigen::Vector3d centre = bb.center();
  auto touches = [&](const ConvexShape& s) {
    return std::any_of(parts.begin(), parts.end(), [&](const ConvexShape& p) { return overlap(p, s); });
  };
  BodyContact hit;
  hit.hit = true;

  std::vector<uint32_t> cand;
  if (nx_ > 0 && bb.max().x() >= gx_ && bb.max().y() >= gy_ && bb.min().x() <= gx_ + nx_ * cell_ &&
      bb.min().y() <= gy_ + ny_ * cell_) {
    const auto [i0, i1, j0, j1] = cellRange(bb);
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i)
        for (size_t e = cell_start_[size_t(j * nx_ + i)]; e < cell_start_[size_t(j * nx_ + i) + 1]; ++e)
          if (entries_[e].zmax >= z0 && entries_[e].zmin <= z1) cand.push_back(entries_[e].tri);
  }
  std::sort(cand.begin(), cand.end());
  cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  const Eigen::Rotation2Dd to_base(-yaw);
  for (uint32_t t : cand) {
    const Eigen::Vector3d a = vertex(t, 0), b = vertex(t, 1), c = vertex(t, 2);
    Eigen::AlignedBox3d tbox(a);
    tbox.extend(b).extend(c);
    if (!tbox.intersects(bb) || !touches(ConvexShape::triangle(a, b, c))) continue;
    hit.what = "map", hit.triangle = t, hit.label = mesh_.labelOf(t);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (const Eigen::Vector3d& v : {a, b, c}) {
      const Eigen::Vector2d local = to_base * (v.head<2>() - Eigen::Vector2d(x, y));
      if (v.z() >= z0 && v.z() <= z1 &&
          std::any_of(pieces_.begin(), pieces_.end(), [&](const auto& p) { return insidePolygon(p, local); }))
        sum += v, ++n;
    }
    hit.where = n > 0 ? Eigen::Vector3d(sum / n) : closestPointOnTriangle(centre, a, b, c);
    hit.where = hit.where.cwiseMax(bb.min()).cwiseMin(bb.max());
    return hit;
  }

  if (people) {
    // A scene without per-person ranges counts as one person holding all boxes.
    const size_t np = people->ranges.empty() ? (people->boxes.empty() ? 0 : 1) : people->ranges.size();
    for (size_t p = 0; p < np; ++p) {
      if (p < people->bounds.size() && !people->bounds[p].cast<double>().intersects(bb)) continue;
      const auto [first, last] =
          people->ranges.empty() ? std::pair{size_t{0}, people->boxes.size()} : people->ranges[p];
      for (size_t k = first; k < last && k < people->boxes.size(); ++k) {
        const OrientedBox& box = people->boxes[k];
        const Eigen::Matrix3d r = box.rotation.cast<double>();
        const Eigen::Vector3d c = box.centre.cast<double>(), half = box.half.cast<double>();
        if (!touches(ConvexShape::box(c, r, half))) continue;
        hit.what = "person", hit.label = "person " + std::to_string(p);
        const Eigen::Vector3d near = c + r * (r.transpose() * (centre - c)).cwiseMax(-half).cwiseMin(half);
        hit.where = near.cwiseMax(bb.min()).cwiseMin(bb.max());
        return hit;
      }
    }
  }
  return {};
}

}  // namespace polyloc
