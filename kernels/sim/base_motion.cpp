#include <polyloc/sim/base_motion.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

namespace {

constexpr double kSubstep = 0.01;           // s, longest integration step
constexpr int64_t kMaxLeadNs = 1000000000;  // a stamp may lead the base clock by 1 s

void checkPositive(double v, const char* name) {
  if (!std::isfinite(v) || v <= 0) throw std::invalid_argument(fmt::format("BaseLimits.{} = {}: must be > 0", name, v));
}

}  // namespace

BaseMotion::BaseMotion(Kinematics k, const BaseLimits& limits, const Pose& start, int64_t t0_ns)
    : kin_(k), lim_(limits), x_(start.x()), y_(start.y()), yaw_(start.yaw()), now_(t0_ns) {
  checkPositive(lim_.max_v, "max_v");
  checkPositive(lim_.max_vy, "max_vy");
  checkPositive(lim_.max_w, "max_w");
  checkPositive(lim_.max_acc, "max_acc");
  checkPositive(lim_.max_acc_y, "max_acc_y");
  checkPositive(lim_.max_acc_w, "max_acc_w");
  checkPositive(lim_.command_timeout, "command_timeout");
  if (!std::isfinite(x_) || !std::isfinite(y_) || !std::isfinite(yaw_))
    throw std::invalid_argument(fmt::format("BaseMotion start pose ({}, {}, yaw {}) is not finite", x_, y_, yaw_));
  pose_ = Pose::planar(x_, y_, yaw_);
}

void BaseMotion::place(const Pose& p) {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.yaw()))
    throw std::invalid_argument(fmt::format("BaseMotion::place: pose ({}, {}, yaw {}) is not finite", p.x(), p.y(), p.yaw()));
  x_ = p.x(), y_ = p.y();
  yaw_ += std::remainder(p.yaw() - yaw_, 2 * M_PI);  // stays unwrapped
  pose_ = Pose::planar(x_, y_, yaw_);
}

bool BaseMotion::command(const VelocityCommand& c, std::string* why) {
  auto reject = [&](std::string msg) {
    ++counters_.rejected;
    if (why) *why = std::move(msg);
    return false;
  };
  const struct {
    const char* name;
    double value, limit;
  } fields[3] = {{"vx", c.vx, lim_.max_v}, {"vy", c.vy, lim_.max_vy}, {"wz", c.wz, lim_.max_w}};
  for (const auto& f : fields) {
    if (!std::isfinite(f.value)) return reject(fmt::format("{} = {} is not finite", f.name, f.value));
    // Far beyond any limit is a broken sender (uninitialised memory, unit mix-up), not a request.
    const double bound = std::max(100 * f.limit, 1.0);
    if (std::abs(f.value) > bound)
      return reject(fmt::format("{} = {} is beyond {} (100x its limit)", f.name, f.value, bound));
  }
  if (has_stamp_ && c.stamp_ns < last_stamp_ns_)
    return reject(fmt::format("stamp_ns = {} is older than the last accepted one, {}", c.stamp_ns, last_stamp_ns_));
  if (c.stamp_ns > now_ && static_cast<uint64_t>(c.stamp_ns) - static_cast<uint64_t>(now_) > uint64_t(kMaxLeadNs))
    return reject(fmt::format("stamp_ns = {} is more than 1 s ahead of the base clock {}", c.stamp_ns, now_));

  ++counters_.accepted;
  double vy = c.vy;
  if (kin_ == Kinematics::Differential && vy != 0) ++counters_.lateral_on_differential, vy = 0;
  const BaseTwist t{std::clamp(c.vx, -lim_.max_v, lim_.max_v), std::clamp(vy, -lim_.max_vy, lim_.max_vy),
                    std::clamp(c.wz, -lim_.max_w, lim_.max_w)};
  if (t.vx != c.vx || t.vy != vy || t.wz != c.wz) ++counters_.clamped;
  target_ = t;
  last_stamp_ns_ = c.stamp_ns;
  has_stamp_ = true;
  last_rx_ns_ = now_;
  timed_out_ = false;
  return true;
}

void BaseMotion::stop() {
  vel_ = {};
  target_ = {};
}

void BaseMotion::advance(int64_t t_ns) {
  if (t_ns < now_) {
    ++counters_.time_backwards;
    return;
  }
  const double amax[3] = {lim_.max_acc, lim_.max_acc_y, lim_.max_acc_w};
  double rem = static_cast<double>(t_ns - now_) * 1e-9;
  // Seconds from now_ until the watchdog fires.
  double deadline = timed_out_ ? std::numeric_limits<double>::infinity()
                               : static_cast<double>(last_rx_ns_ - now_) * 1e-9 + lim_.command_timeout;
  while (rem > 0) {
    if (deadline <= 0) {
      timed_out_ = true, ++counters_.timeouts, target_ = {};
      deadline = std::numeric_limits<double>::infinity();
    }
    const double v[3] = {vel_.vx, vel_.vy, vel_.wz}, g[3] = {target_.vx, target_.vy, target_.wz};
    if (v[0] == 0 && v[1] == 0 && v[2] == 0 && g[0] == 0 && g[1] == 0 && g[2] == 0) {
      // At rest with nothing to do: skip ahead (the watchdog may still fire on the way).
      if (deadline <= rem) timed_out_ = true, ++counters_.timeouts;
      break;
    }
    // One piece: each axis accelerates uniformly (or holds) throughout; pieces end where an axis
    // reaches its target or the watchdog fires, so the mean velocity gives the exact distance on a
    // line (and a second-order arc while the turn rate changes).
    double reach[3], h = std::min({rem, kSubstep, deadline});
    for (int k = 0; k < 3; ++k) {
      reach[k] = std::abs(g[k] - v[k]) / amax[k];
      if (reach[k] > 0) h = std::min(h, reach[k]);
    }
    double n[3];
    for (int k = 0; k < 3; ++k) n[k] = reach[k] <= h ? g[k] : v[k] + std::copysign(amax[k] * h, g[k] - v[k]);
    integrate({0.5 * (v[0] + n[0]), 0.5 * (v[1] + n[1]), 0.5 * (v[2] + n[2])}, h);
    vel_ = {n[0], n[1], n[2]};
    rem -= h;
    deadline -= h;
  }
  now_ = t_ns;
  pose_ = Pose::planar(x_, y_, yaw_);
}

// Constant base-frame twist over dt: the base moves along a circular arc (a line when wz = 0).
void BaseMotion::integrate(const BaseTwist& m, double dt) {
  const double th = m.wz * dt;
  // a = integral of cos(wz s), b = integral of sin(wz s) over [0, dt]; 2 sin^2 avoids 1 - cos.
  double a = dt, b = 0;
  if (m.wz != 0) {
    const double s = std::sin(0.5 * th);
    a = std::sin(th) / m.wz, b = 2 * s * s / m.wz;
  }
  const double dx = a * m.vx - b * m.vy, dy = b * m.vx + a * m.vy;  // base frame at the piece start
  const double c = std::cos(yaw_), s = std::sin(yaw_);
  x_ += c * dx - s * dy;
  y_ += s * dx + c * dy;
  yaw_ += th;
}

}  // namespace polyloc
