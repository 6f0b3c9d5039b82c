#include <polyloc/geometry/pose.hpp>
#include <polyloc/sim/trajectory.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

namespace {

// Position along a trapezoidal (or triangular) angle profile of |angle| = total.
double turnProgress(double total, double rate, double acc, double tau, double* duration) {
  const double ta_full = rate / acc;
  double ta, tc, peak;
  if (total >= rate * ta_full) {
    ta = ta_full, peak = rate, tc = (total - rate * ta_full) / rate;
  } else {
    ta = std::sqrt(total / acc), peak = acc * ta, tc = 0;
  }
  if (duration) *duration = 2 * ta + tc;
  if (tau <= 0) return 0;
  if (tau < ta) return 0.5 * acc * tau * tau;
  if (tau < ta + tc) return 0.5 * acc * ta * ta + peak * (tau - ta);
  const double td = std::min(tau - ta - tc, ta);
  return std::min(total, 0.5 * acc * ta * ta + peak * tc + peak * td - 0.5 * acc * td * td);
}

}  // namespace

Trajectory::Trajectory(const RouteSpec& route, Kinematics kinematics) : kin_(kinematics), route_(route) {
  const auto& wp = route.waypoints;
  if (wp.empty()) throw std::invalid_argument("route: needs at least one waypoint");
  if (!(route.max_speed > 0 && route.max_acceleration > 0 && route.max_yaw_rate > 0 &&
        route.max_yaw_acceleration > 0 && route.max_lateral_acceleration > 0 && route.spacing > 0))
    throw std::invalid_argument("route: speed, acceleration and spacing limits must be positive");

  // Split the waypoints into legs at stops; remember the route arc length of every waypoint.
  std::vector<SplinePath> paths;
  std::vector<double> s0s;
  std::vector<std::vector<size_t>> leg_waypoints;
  std::vector<size_t> current{0};
  double s_total = 0;
  std::vector<double> wp_s(wp.size(), 0.0);
  auto closeLeg = [&] {
    std::vector<Eigen::Vector2d> pts;
    for (size_t i : current) pts.push_back(wp[i].p);
    std::vector<int> index;
    std::vector<Eigen::Vector2d> dense = densifyPolyline(pts, route.spacing, &index);
    if (dense.size() >= 2) {
      paths.emplace_back(dense);
      for (size_t k = 0; k < current.size(); ++k)
        wp_s[current[k]] = s_total + (index[k] >= 0 ? paths.back().knotS(index[k]) : 0.0);
      s0s.push_back(s_total);
      leg_waypoints.push_back(current);
      s_total += paths.back().length();
    } else {
      for (size_t i : current) wp_s[i] = s_total;
    }
  };
  for (size_t i = 1; i < wp.size(); ++i) {
    current.push_back(i);
    if (i + 1 < wp.size() && (wp[i].stop || wp[i].wait > 0)) {
      closeLeg();
      current = {i};
    }
  }
  closeLeg();

  // Omni headings: anchors at the waypoints that give one, interpolated along the route.
  if (kin_ == Kinematics::Omni) {
    if (route.heading) {
      anchors_.push_back({0.0, *route.heading});
    } else {
      for (size_t i = 0; i < wp.size(); ++i) {
        if (!wp[i].heading) continue;
        const double h = anchors_.empty()
                             ? *wp[i].heading
                             : anchors_.back().second + angleDiff(*wp[i].heading, anchors_.back().second);
        if (!anchors_.empty() && wp_s[i] <= anchors_.back().first) anchors_.back().second = h;
        else anchors_.push_back({wp_s[i], h});
      }
    }
  }

  // Speed caps in curves: lateral acceleration, and the yaw rate the heading change needs.
  for (size_t l = 0; l < paths.size(); ++l) legs_.push_back({paths[l], SpeedProfile(0.0, {1, 1}), s0s[l]});
  for (size_t l = 0; l < legs_.size(); ++l) {
    auto limit = [&](double s) {
      double cap = std::numeric_limits<double>::infinity();
      const double k = std::abs(legs_[l].path.curvature(s));
      if (k > 1e-9) cap = std::min(cap, std::sqrt(route.max_lateral_acceleration / k));
      const double slope = std::abs(headingSlope(l, s));
      if (slope > 1e-9) cap = std::min(cap, route.max_yaw_rate / slope);
      return cap;
    };
    std::vector<double> kinks;  // curvature has corners at the knots, the heading slope at anchors
    for (size_t k = 0; k < legs_[l].path.numKnots(); ++k) kinks.push_back(legs_[l].path.knotS(k));
    for (const auto& a : anchors_) kinks.push_back(a.first - legs_[l].s0);
    legs_[l].profile = SpeedProfile(legs_[l].path.length(), {route.max_speed, route.max_acceleration},
                                    limit, 0.01, kinks);
  }

  // Timeline: pause at the start, then per leg: drive, wait at its end, turn towards the next.
  double t = 0;
  const Eigen::Vector2d p0 = wp.front().p;
  double yaw = legs_.empty() ? (wp.front().heading ? *wp.front().heading : 0.0) : headingOn(0, 0);
  phases_.push_back({Phase::Pause, t, t + route.start_pause, 0, p0.x(), p0.y(), yaw, 0, 0});
  t += route.start_pause;
  for (size_t l = 0; l < legs_.size(); ++l) {
    const Leg& leg = legs_[l];
    phases_.push_back({Phase::Drive, t, t + leg.profile.duration(), l, 0, 0, 0, 0, 0});
    t += leg.profile.duration();
    const Eigen::Vector2d end = leg.path.position(leg.path.length());
    const double s_end = leg.s0 + leg.path.length();
    yaw = headingOn(l, leg.path.length());
    const size_t last_wp = leg_waypoints[l].back();
    if (wp[last_wp].wait > 0) {
      phases_.push_back({Phase::Pause, t, t + wp[last_wp].wait, l, end.x(), end.y(), yaw, 0, s_end});
      t += wp[last_wp].wait;
    }
    if (l + 1 < legs_.size()) {
      const double dyaw = angleDiff(headingOn(l + 1, 0), yaw);
      double dur = 0;
      turnProgress(std::abs(dyaw), route.max_yaw_rate, route.max_yaw_acceleration, 0, &dur);
      if (std::abs(dyaw) > 1e-9) {
        phases_.push_back({Phase::Turn, t, t + dur, l, end.x(), end.y(), yaw, dyaw, s_end});
        t += dur;
      }
    }
  }
}

double Trajectory::duration() const { return phases_.back().t1; }

double Trajectory::length() const {
  return legs_.empty() ? 0.0 : legs_.back().s0 + legs_.back().path.length();
}

double Trajectory::headingOn(size_t leg, double s) const {
  if (kin_ == Kinematics::Differential || anchors_.empty()) return legs_[leg].path.heading(s);
  const double S = legs_[leg].s0 + s;
  if (S <= anchors_.front().first) return wrapAngle(anchors_.front().second);
  for (size_t i = 1; i < anchors_.size(); ++i) {
    if (S <= anchors_[i].first) {
      const auto [sa, ha] = anchors_[i - 1];
      const auto [sb, hb] = anchors_[i];
      return wrapAngle(ha + (hb - ha) * (S - sa) / (sb - sa));
    }
  }
  return wrapAngle(anchors_.back().second);
}

double Trajectory::headingSlope(size_t leg, double s) const {
  if (kin_ == Kinematics::Differential || anchors_.empty()) return legs_[leg].path.curvature(s);
  const double S = legs_[leg].s0 + s;
  for (size_t i = 1; i < anchors_.size(); ++i)
    if (S >= anchors_[i - 1].first && S <= anchors_[i].first)
      return (anchors_[i].second - anchors_[i - 1].second) / (anchors_[i].first - anchors_[i - 1].first);
  return 0.0;
}

PlanarState Trajectory::at(double t) const {
  auto it = std::upper_bound(phases_.begin(), phases_.end(), t,
                             [](double v, const Phase& p) { return v < p.t0; });
  const Phase& ph = it == phases_.begin() ? phases_.front() : *(it - 1);
  PlanarState st;
  if (ph.kind == Phase::Drive) {
    const Leg& leg = legs_[ph.leg];
    const SpeedProfile::State sp = leg.profile.at(t - ph.t0);
    const Eigen::Vector2d p = leg.path.position(sp.s), d = leg.path.tangent(sp.s);
    st.x = p.x(), st.y = p.y();
    st.yaw = headingOn(ph.leg, sp.s);
    st.vx = d.x() * sp.v, st.vy = d.y() * sp.v;
    st.omega = headingSlope(ph.leg, sp.s) * sp.v;
    st.s = leg.s0 + sp.s;
    return st;
  }
  st.x = ph.x, st.y = ph.y, st.s = ph.s, st.yaw = ph.yaw0;
  if (ph.kind == Phase::Turn) {
    const double tau = std::min(t, ph.t1) - ph.t0, total = std::abs(ph.dyaw);
    const double a = turnProgress(total, route_.max_yaw_rate, route_.max_yaw_acceleration, tau, nullptr);
    const double h = 1e-4;
    const double a2 = turnProgress(total, route_.max_yaw_rate, route_.max_yaw_acceleration, tau + h, nullptr);
    const double sign = ph.dyaw < 0 ? -1.0 : 1.0;
    st.yaw = wrapAngle(ph.yaw0 + sign * a);
    st.omega = t < ph.t1 ? sign * (a2 - a) / h : 0.0;
  }
  return st;
}

std::vector<PlanarState> Trajectory::sample(double spacing) const {
  std::vector<PlanarState> out;
  for (size_t l = 0; l < legs_.size(); ++l) {
    const SplinePath& p = legs_[l].path;
    const int n = std::max(1, static_cast<int>(std::ceil(p.length() / spacing)));
    for (int k = 0; k <= n; ++k) {
      const double s = p.length() * k / n;
      PlanarState st;
      const Eigen::Vector2d q = p.position(s);
      st.x = q.x(), st.y = q.y(), st.yaw = headingOn(l, s), st.s = legs_[l].s0 + s;
      out.push_back(st);
    }
  }
  if (out.empty()) {
    PlanarState st;
    st.x = route_.waypoints.front().p.x(), st.y = route_.waypoints.front().p.y();
    out.push_back(st);
  }
  return out;
}

}  // namespace polyloc
