// Smooth robot paths: a natural cubic spline (C2) through 2D points, parametrised by arc length,
// so that position(s) moves at unit speed along the curve and a speed profile v(s) is exactly
// the robot's speed. Waypoints are densified first (densifyPolyline): a spline through sparse
// waypoints bulges far away from the straight lines between them, through dense ones it follows
// them and rounds the corners within about one spacing.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace polyloc {

// Inserts evenly spaced points on every segment so that neighbours are at most `spacing` apart.
// Consecutive duplicates are dropped. Returns, in `index_of` (when given), the index in the
// result of every input point (-1 for dropped duplicates).
std::vector<Eigen::Vector2d> densifyPolyline(const std::vector<Eigen::Vector2d>& points,
                                             double spacing, std::vector<int>* index_of = nullptr);

class SplinePath {
 public:
  // Throws std::invalid_argument for fewer than 2 distinct points. Knots are at cumulative
  // chord length; the ends are natural (zero second derivative).
  explicit SplinePath(std::vector<Eigen::Vector2d> points);

  double length() const { return length_; }
  size_t numKnots() const { return p_.size(); }
  double knotS(size_t i) const { return knot_s_[i]; }  // arc length at knot i
  const Eigen::Vector2d& knot(size_t i) const { return p_[i]; }

  // All take arc length s, clamped to [0, length].
  Eigen::Vector2d position(double s) const;
  Eigen::Vector2d tangent(double s) const;  // unit dp/ds
  double heading(double s) const;           // atan2 of the tangent
  double curvature(double s) const;         // signed, 1/m (left turn positive)

  // Spline parameter (chord length) at arc length s; exposed for tests.
  double parameterAt(double s) const;
  // Derivatives with respect to the spline parameter t (chord length), order 0..3.
  Eigen::Vector2d evalT(double t, int order) const;

 private:
  double speedT(double t) const { return evalT(t, 1).norm(); }
  double arcLengthT(double t0, double t1) const;  // Gauss-Legendre

  std::vector<Eigen::Vector2d> p_, m_;  // knots and second derivatives
  std::vector<double> t_;               // knot parameters (cumulative chord length)
  std::vector<double> knot_s_;          // arc length at each knot
  std::vector<double> table_t_, table_s_;  // dense (t, s) table for inverting s(t)
  double length_ = 0;
};

}  // namespace polyloc
