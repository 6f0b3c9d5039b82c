#include <polyloc/sim/profile.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

SpeedProfile::SpeedProfile(double length, const SpeedLimits& lim,
                           const std::function<double(double)>& limit, double ds,
                           const std::vector<double>& kinks)
    : length_(length) {
  if (!(length >= 0)) throw std::invalid_argument("SpeedProfile: negative length");
  if (!(lim.max_speed > 0) || !(lim.max_acceleration > 0))
    throw std::invalid_argument("SpeedProfile: max_speed and max_acceleration must be positive");
  const size_t n = std::max<size_t>(1, static_cast<size_t>(std::ceil(length / ds)));
  ds_ = length / static_cast<double>(n);
  std::vector<double> cap(n + 1);
  // The cap of a grid point also holds half a cell to either side: the speed within a cell lies
  // between its end speeds, so the limit then holds between the grid points too.
  for (size_t i = 0; i <= n; ++i) {
    double c = std::numeric_limits<double>::infinity();
    if (limit) {
      c = limit(i * ds_);
      if (i > 0) c = std::min(c, limit((i - 0.5) * ds_));
      if (i < n) c = std::min(c, limit((i + 0.5) * ds_));
    }
    cap[i] = std::max(0.0, std::min(lim.max_speed, c));
  }
  for (double k : kinks) {  // a corner inside a cell caps both its ends
    if (!limit || !(k > 0 && k < length)) continue;
    const size_t i = std::min(static_cast<size_t>(k / ds_), n - 1);
    const double c = std::max(0.0, limit(k));
    cap[i] = std::min(cap[i], c), cap[i + 1] = std::min(cap[i + 1], c);
  }
  v_.assign(n + 1, 0.0);
  cap[0] = cap[n] = 0.0;  // start and stop at rest
  const double two_a_ds = 2.0 * lim.max_acceleration * ds_;
  for (size_t i = 1; i <= n; ++i) v_[i] = std::min(cap[i], std::sqrt(v_[i - 1] * v_[i - 1] + two_a_ds));
  for (size_t i = n; i-- > 0;) v_[i] = std::min(v_[i], std::sqrt(v_[i + 1] * v_[i + 1] + two_a_ds));
  // A cell with zero speed at both ends only happens under a zero cap; creep through it.
  for (size_t i = 0; i < n; ++i)
    if (v_[i] + v_[i + 1] <= 0.0) v_[i + 1] = std::min(std::sqrt(two_a_ds), lim.max_speed);
  time_.assign(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) time_[i + 1] = time_[i] + (ds_ > 0 ? 2.0 * ds_ / (v_[i] + v_[i + 1]) : 0.0);
}

SpeedProfile::State SpeedProfile::at(double tau) const {
  if (tau <= 0 || length_ <= 0) return {0, 0, 0};
  if (tau >= time_.back()) return {length_, 0, 0};
  size_t i = std::upper_bound(time_.begin(), time_.end(), tau) - time_.begin() - 1;
  i = std::min(i, v_.size() - 2);
  const double v0 = v_[i], v1 = v_[i + 1];
  const double a = (v1 * v1 - v0 * v0) / (2.0 * ds_);
  const double dt = tau - time_[i];
  const double s = std::min(i * ds_ + v0 * dt + 0.5 * a * dt * dt, length_);
  return {s, std::max(0.0, v0 + a * dt), a};
}

double SpeedProfile::speedAt(double s) const {
  if (length_ <= 0) return 0;
  const double x = std::clamp(s / ds_, 0.0, static_cast<double>(v_.size() - 1));
  const size_t i = std::min(static_cast<size_t>(x), v_.size() - 2);
  const double f = x - i;
  return std::sqrt((1 - f) * v_[i] * v_[i] + f * v_[i + 1] * v_[i + 1]);
}

}  // namespace polyloc
