#include <polyloc/mcl/line_segments.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <utility>

namespace polyloc {

namespace {

// Largest orthogonal distance of pts[i, j) to the chord pts[i] -> pts[j - 1], and where.
std::pair<double, size_t> farthestFromChord(std::span<const Eigen::Vector3d> pts, size_t i, size_t j) {
  const Eigen::Vector3d a = pts[i];
  Eigen::Vector3d d = pts[j - 1] - a;
  const double len = d.norm();
  double best = 0;
  size_t at = i;
  for (size_t k = i + 1; k + 1 < j; ++k) {
    const Eigen::Vector3d v = pts[k] - a;
    const double dist = len > 1e-12 ? v.cross(d).norm() / len : v.norm();
    if (dist > best) best = dist, at = k;
  }
  return {best, at};
}

double maxDistance(std::span<const Eigen::Vector3d> pts, const LineSegment& s) {
  double m = 0;
  for (const auto& p : pts) m = std::max(m, (p - s.a).cross(s.dir).norm());
  return m;
}

}  // namespace

LineSegment fitLine(std::span<const Eigen::Vector3d> pts) {
  LineSegment s;
  s.points = pts.size();
  if (pts.empty()) return s;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  c /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  // Principal axis of the scatter: the direction that minimises orthogonal distances.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d d = es.eigenvectors().col(2);
  if (d.dot(pts.back() - pts.front()) < 0) d = -d;  // point from the first to the last point
  s.dir = d;
  s.a = c + d * d.dot(pts.front() - c);
  s.b = c + d * d.dot(pts.back() - c);
  double ss = 0;
  for (const auto& p : pts) ss += (p - c).cross(d).squaredNorm();
  s.rms = std::sqrt(ss / double(pts.size()));
  return s;
}

std::vector<LineSegment> fitLineSegments(std::span<const float> ranges, const BeamSet& beams,
                                         const LineFitParams& prm) {
  const size_t n = std::min(ranges.size(), beams.size());
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(n);
  for (size_t b = 0; b < n; ++b) {
    const float r = ranges[b];
    if (!std::isfinite(r) || r < beams.range_min || r >= beams.range_max) continue;
    pts.emplace_back(double(r) * beams.dx[b], double(r) * beams.dy[b], double(r) * beams.dz[b]);
  }
  // Runs of points without gaps: [begin, end) index pairs.
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t i = 0; i < pts.size();) {
    size_t j = i + 1;
    while (j < pts.size() && (pts[j] - pts[j - 1]).norm() <= prm.max_gap) ++j;
    if (j - i >= std::max<size_t>(prm.min_points, 2)) runs.emplace_back(i, j);
    i = j;
  }
  const std::span<const Eigen::Vector3d> all(pts);
  std::vector<LineSegment> out;
  for (const auto& [r0, r1] : runs) {
    // Split: an explicit stack instead of recursion (a long run must not exhaust the stack);
    // pieces come out in scan order because the right half is pushed first.
    std::vector<std::pair<size_t, size_t>> pieces, stack{{r0, r1}};
    while (!stack.empty()) {
      const auto [i, j] = stack.back();
      stack.pop_back();
      const auto [dist, k] = j - i > 2 ? farthestFromChord(all, i, j) : std::pair<double, size_t>{0.0, i};
      if (dist > prm.split_threshold && k > i && k + 1 < j) {
        stack.emplace_back(k, j);
        stack.emplace_back(i, k);
      } else {
        pieces.emplace_back(i, j);
      }
    }
    // Merge: neighbours whose union still fits one line. The rms test undoes splits at single
    // noise spikes (one point beyond the threshold), which the max test alone would keep.
    std::vector<std::pair<size_t, size_t>> merged;
    for (const auto& pc : pieces) {
      if (!merged.empty()) {
        const size_t i = merged.back().first, j = pc.second;
        const auto span = all.subspan(i, j - i);
        const LineSegment u = fitLine(span);
        if (maxDistance(span, u) <= prm.split_threshold || u.rms <= prm.split_threshold / 2) {
          merged.back().second = j;
          continue;
        }
      }
      merged.push_back(pc);
    }
    for (const auto& [i, j] : merged) {
      if (j - i < prm.min_points) continue;
      LineSegment s = fitLine(all.subspan(i, j - i));
      if (s.length() >= prm.min_length) out.push_back(s);
    }
  }
  return out;
}

}  // namespace polyloc
