#include <polynav/path_follow.hpp>

#include <algorithm>
#include <cmath>

namespace polynav {

PathFollow::PathFollow(std::vector<Eigen::Vector2d> path) : path_(std::move(path)) {
  cum_.assign(path_.size(), 0.0);
  for (size_t i = 1; i < path_.size(); ++i) cum_[i] = cum_[i - 1] + (path_[i] - path_[i - 1]).norm();
}

double PathFollow::update(const Eigen::Vector2d& p, double window_m) {
  if (path_.empty()) return INFINITY;
  if (path_.size() == 1) return (p - path_[0]).norm();
  double best = INFINITY;
  size_t best_seg = seg_;
  double best_s = s_;
  for (size_t i = seg_; i + 1 < path_.size() && cum_[i] <= s_ + window_m; ++i) {
    const Eigen::Vector2d a = path_[i], d = path_[i + 1] - a;
    const double len2 = d.squaredNorm();
    double u = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    if (i == seg_ && len2 > 0) u = std::max(u, (s_ - cum_[i]) / std::sqrt(len2));  // never backwards
    const double dist = (a + u * d - p).norm();
    if (dist < best - 1e-12) best = dist, best_seg = i, best_s = cum_[i] + u * std::sqrt(len2);
  }
  seg_ = best_seg, s_ = best_s;
  return best;
}

Eigen::Vector2d PathFollow::at(double s) const {
  if (path_.empty()) return Eigen::Vector2d::Zero();
  if (s <= 0) return path_.front();
  if (s >= cum_.back()) return path_.back();
  const size_t i = size_t(std::upper_bound(cum_.begin(), cum_.end(), s) - cum_.begin()) - 1;
  const double len = cum_[i + 1] - cum_[i];
  return len > 0 ? Eigen::Vector2d(path_[i] + (path_[i + 1] - path_[i]) * ((s - cum_[i]) / len)) : path_[i];
}

Eigen::Vector2d PathFollow::carrot(double ahead_m) const { return at(s_ + ahead_m); }

Eigen::Vector2d PathFollow::direction(double ahead_m) const {
  if (path_.size() < 2) return {1, 0};
  const double s = std::min(s_ + ahead_m, cum_.back());
  const Eigen::Vector2d a = at(std::max(0.0, s - 0.1)), b = at(std::min(cum_.back(), s + 0.1));
  const Eigen::Vector2d d = b - a;
  return d.norm() > 1e-9 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d(1, 0);
}

double PathFollow::turnAhead(double ahead_m) const {
  if (path_.size() < 2) return 0;
  const Eigen::Vector2d d0 = direction(0);
  double worst = 0;
  for (double s = 0.1; s <= ahead_m + 1e-9; s += 0.1) {
    const Eigen::Vector2d d = direction(s);
    worst = std::max(worst, std::abs(std::atan2(d0.x() * d.y() - d0.y() * d.x(), d0.dot(d))));
  }
  return worst;
}

double PathFollow::remaining() const { return path_.empty() ? 0 : cum_.back() - s_; }

}  // namespace polynav
