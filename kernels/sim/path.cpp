#include <polyloc/sim/path.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {

std::vector<Eigen::Vector2d> densifyPolyline(const std::vector<Eigen::Vector2d>& points,
                                             double spacing, std::vector<int>* index_of) {
  if (!(spacing > 0)) throw std::invalid_argument("densifyPolyline: spacing must be positive");
  std::vector<Eigen::Vector2d> out;
  if (index_of) index_of->assign(points.size(), -1);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!out.empty()) {
      const Eigen::Vector2d a = out.back(), b = points[i];
      const double d = (b - a).norm();
      if (d < 1e-9) continue;  // duplicate
      const int n = static_cast<int>(std::ceil(d / spacing - 1e-9));
      for (int k = 1; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
    }
    out.push_back(points[i]);
    if (index_of) (*index_of)[i] = static_cast<int>(out.size()) - 1;
  }
  return out;
}

SplinePath::SplinePath(std::vector<Eigen::Vector2d> points) {
  for (const auto& q : points)
    if (p_.empty() || (q - p_.back()).norm() > 1e-9) p_.push_back(q);
  const size_t n = p_.size();
  if (n < 2) throw std::invalid_argument("SplinePath: needs at least 2 distinct points");
  t_.assign(n, 0.0);
  for (size_t i = 1; i < n; ++i) t_[i] = t_[i - 1] + (p_[i] - p_[i - 1]).norm();

  // Natural spline: M_0 = M_{n-1} = 0; tridiagonal system for the interior (Thomas algorithm).
  m_.assign(n, Eigen::Vector2d::Zero());
  if (n > 2) {
    const size_t k = n - 2;
    std::vector<double> a(k), b(k), c(k);
    std::vector<Eigen::Vector2d> d(k);
    for (size_t j = 0; j < k; ++j) {
      const size_t i = j + 1;
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      a[j] = h0 / 6, b[j] = (h0 + h1) / 3, c[j] = h1 / 6;
      d[j] = (p_[i + 1] - p_[i]) / h1 - (p_[i] - p_[i - 1]) / h0;
    }
    for (size_t j = 1; j < k; ++j) {
      const double w = a[j] / b[j - 1];
      b[j] -= w * c[j - 1];
      d[j] -= w * d[j - 1];
    }
    m_[k] = d[k - 1] / b[k - 1];
    for (size_t j = k - 1; j-- > 0;) m_[j + 1] = (d[j] - c[j] * m_[j + 2]) / b[j];
  }

  // Arc length table: 32 sub-intervals per segment, each integrated with 5-point Gauss-Legendre.
  constexpr int kSub = 32;
  table_t_.push_back(0.0);
  table_s_.push_back(0.0);
  knot_s_.assign(n, 0.0);
  for (size_t i = 0; i + 1 < n; ++i) {
    for (int j = 1; j <= kSub; ++j) {
      const double ta = t_[i] + (t_[i + 1] - t_[i]) * (j - 1) / kSub;
      const double tb = j == kSub ? t_[i + 1] : t_[i] + (t_[i + 1] - t_[i]) * j / kSub;
      table_t_.push_back(tb);
      table_s_.push_back(table_s_.back() + arcLengthT(ta, tb));
    }
    knot_s_[i + 1] = table_s_.back();
  }
  length_ = table_s_.back();
}

Eigen::Vector2d SplinePath::evalT(double t, int order) const {
  t = std::clamp(t, t_.front(), t_.back());
  size_t i = std::upper_bound(t_.begin(), t_.end(), t) - t_.begin();
  i = std::clamp<size_t>(i, 1, t_.size() - 1) - 1;  // segment [t_i, t_{i+1}]
  const double h = t_[i + 1] - t_[i], a = t_[i + 1] - t, b = t - t_[i];
  const Eigen::Vector2d &M0 = m_[i], &M1 = m_[i + 1], &P0 = p_[i], &P1 = p_[i + 1];
  const Eigen::Vector2d C0 = P0 / h - M0 * h / 6, C1 = P1 / h - M1 * h / 6;
  switch (order) {
    case 0: return M0 * a * a * a / (6 * h) + M1 * b * b * b / (6 * h) + C0 * a + C1 * b;
    case 1: return -M0 * a * a / (2 * h) + M1 * b * b / (2 * h) - C0 + C1;
    case 2: return M0 * a / h + M1 * b / h;
    default: return (M1 - M0) / h;
  }
}

double SplinePath::arcLengthT(double t0, double t1) const {
  static constexpr double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                  0.5384693101056831, 0.9061798459386640};
  static constexpr double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                  0.4786286704993665, 0.2369268850561891};
  const double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0);
  double s = 0;
  for (int k = 0; k < 5; ++k) s += w[k] * speedT(mid + half * x[k]);
  return s * half;
}

double SplinePath::parameterAt(double s) const {
  s = std::clamp(s, 0.0, length_);
  size_t j = std::upper_bound(table_s_.begin(), table_s_.end(), s) - table_s_.begin();
  j = std::clamp<size_t>(j, 1, table_s_.size() - 1) - 1;
  const double t0 = table_t_[j], t1 = table_t_[j + 1], s0 = table_s_[j];
  const double ds = table_s_[j + 1] - s0;
  double t = ds > 0 ? t0 + (t1 - t0) * (s - s0) / ds : t0;
  // Newton on arcLength(t0, t) = s - s0; the speed never vanishes on a chord-length spline
  // through distinct points with the corners densified, and the bracket keeps it safe anyway.
  for (int it = 0; it < 8; ++it) {
    const double f = arcLengthT(t0, t) - (s - s0);
    const double v = speedT(t);
    if (v <= 1e-12) break;
    const double step = f / v;
    t = std::clamp(t - step, t0, t1);
    if (std::abs(step) < 1e-13) break;
  }
  return t;
}

Eigen::Vector2d SplinePath::position(double s) const { return evalT(parameterAt(s), 0); }

Eigen::Vector2d SplinePath::tangent(double s) const {
  const Eigen::Vector2d d = evalT(parameterAt(s), 1);
  const double n = d.norm();
  return n > 0 ? Eigen::Vector2d(d / n) : Eigen::Vector2d(1, 0);
}

double SplinePath::heading(double s) const {
  const Eigen::Vector2d d = tangent(s);
  return std::atan2(d.y(), d.x());
}

double SplinePath::curvature(double s) const {
  const double t = parameterAt(s);
  const Eigen::Vector2d d1 = evalT(t, 1), d2 = evalT(t, 2);
  const double v = d1.norm();
  return v > 1e-12 ? (d1.x() * d2.y() - d1.y() * d2.x()) / (v * v * v) : 0.0;
}

}  // namespace polyloc
