#include <polyloc/sim/people.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc {

namespace {

constexpr double kStride = 1.4;  // m walked per gait cycle (two steps)

// Slab test in the box frame: entry distance, or +inf. `axis` receives the entry face's axis.
float slab(const Eigen::Vector3f& o, const Eigen::Vector3f& d, const Eigen::Vector3f& half,
           float tmin, float tmax, int* axis, float* sign) {
  float t0 = -std::numeric_limits<float>::infinity(), t1 = std::numeric_limits<float>::infinity();
  int ax = 0;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12f) {
      if (o[k] < -half[k] || o[k] > half[k]) return std::numeric_limits<float>::infinity();
      continue;
    }
    const float inv = 1.f / d[k];
    float a = (-half[k] - o[k]) * inv, b = (half[k] - o[k]) * inv;
    if (a > b) std::swap(a, b);
    if (a > t0) t0 = a, ax = k;
    t1 = std::min(t1, b);
  }
  if (t0 > t1 || t1 < tmin || t0 > tmax) return std::numeric_limits<float>::infinity();
  if (axis) *axis = ax, *sign = d[ax] > 0 ? -1.f : 1.f;
  return std::max(t0, tmin);
}

}  // namespace

float PeopleScene::intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tmin,
                             float tmax, Eigen::Vector3f* normal) const {
  float best = std::numeric_limits<float>::infinity();
  for (size_t p = 0; p < bounds.size(); ++p) {
    const Eigen::Vector3f c = bounds[p].center(), h = 0.5f * bounds[p].sizes();
    if (!std::isfinite(slab(o - c, d, h, tmin, std::min(tmax, best), nullptr, nullptr))) continue;
    for (size_t b = ranges[p].first; b < ranges[p].second; ++b) {
      const OrientedBox& box = boxes[b];
      const Eigen::Vector3f lo = box.rotation.transpose() * (o - box.centre);
      const Eigen::Vector3f ld = box.rotation.transpose() * d;
      int axis;
      float sign;
      const float t = slab(lo, ld, box.half, tmin, std::min(tmax, best), &axis, &sign);
      if (t < best) {
        best = t;
        if (normal) *normal = box.rotation.col(axis) * sign;
      }
    }
  }
  return best;
}

People::People(std::vector<PersonSpec> specs) : specs_(std::move(specs)) {
  for (const PersonSpec& s : specs_) {
    std::vector<double> cum{0.0};
    const auto& w = s.waypoints;
    for (size_t i = 1; i < w.size(); ++i) cum.push_back(cum.back() + (w[i] - w[i - 1]).norm());
    if (s.loop && w.size() >= 2) cum.push_back(cum.back() + (w.front() - w.back()).norm());
    cum_.push_back(std::move(cum));
  }
}

PersonState People::state(size_t i, double t, const Eigen::Vector2d& robot) const {
  const PersonSpec& s = specs_[i];
  PersonState st;
  if (t < s.start || t >= s.end) return st;
  st.present = true;
  st.z = s.z;
  // A person who waited for the robot (setDelays) is that much behind on their way.
  const double walked = s.offset + s.speed * std::max(0.0, t - s.start - (i < delays_.size() ? delays_[i] : 0.0));
  if (s.circle) {
    const Eigen::Vector2d c = s.around_robot ? robot : s.centre;
    const double a = walked / s.radius;
    const double dir = s.speed < 0 ? -1.0 : 1.0;
    st.x = c.x() + s.radius * std::cos(a), st.y = c.y() + s.radius * std::sin(a);
    st.yaw = wrapAngle(a + dir * M_PI / 2);
    st.vx = -s.speed * std::sin(a), st.vy = s.speed * std::cos(a);
    st.phase = 2 * M_PI * std::abs(walked) / kStride;
    return st;
  }
  const auto& w = s.waypoints;
  const auto& cum = cum_[i];
  if (w.size() < 2 || cum.back() <= 0) {
    if (!w.empty()) st.x = w.front().x(), st.y = w.front().y();
    return st;
  }
  const double total = cum.back();
  double d = std::abs(walked);
  bool moving = true;
  if (s.loop) {
    d = std::fmod(d, total);
  } else if (d >= total) {
    d = total, moving = false;
  }
  size_t seg = std::upper_bound(cum.begin(), cum.end(), d) - cum.begin();
  seg = std::clamp<size_t>(seg, 1, cum.size() - 1) - 1;
  const Eigen::Vector2d a = w[seg % w.size()], b = w[(seg + 1) % w.size()];
  const double len = cum[seg + 1] - cum[seg];
  const double f = len > 0 ? (d - cum[seg]) / len : 0.0;
  const Eigen::Vector2d p = a + (b - a) * f, dir = len > 0 ? Eigen::Vector2d((b - a) / len) : Eigen::Vector2d(1, 0);
  st.x = p.x(), st.y = p.y(), st.yaw = std::atan2(dir.y(), dir.x());
  if (moving) st.vx = dir.x() * std::abs(s.speed), st.vy = dir.y() * std::abs(s.speed);
  st.phase = moving ? 2 * M_PI * d / kStride : 0.0;  // standing: arms and legs at rest
  return st;
}

void People::addBody(const PersonState& s, double height, std::vector<OrientedBox>& out) {
  const float k = static_cast<float>(height / 1.75);
  const Eigen::Matrix3f yaw = Eigen::AngleAxisf(static_cast<float>(s.yaw), Eigen::Vector3f::UnitZ()).toRotationMatrix();
  const Eigen::Vector3f base(static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z));
  // A part hanging from a pivot (person frame), swung about the person's y axis.
  auto part = [&](const Eigen::Vector3f& pivot, float swing, const Eigen::Vector3f& centre,
                  const Eigen::Vector3f& half) {
    const Eigen::Matrix3f r = Eigen::AngleAxisf(swing, Eigen::Vector3f::UnitY()).toRotationMatrix();
    out.push_back({yaw * r, base + yaw * (pivot + r * centre), half});
  };
  const float sw = static_cast<float>(std::sin(s.phase));
  for (float side : {1.f, -1.f}) {  // legs: 0.14 m square, hip at 0.85 m
    part({0, side * 0.09f, 0.85f * k}, 0.35f * sw * side, {0, 0, -0.425f * k}, {0.07f, 0.07f, 0.425f * k});
  }
  part({0, 0, 0}, 0.f, {0, 0, 1.175f * k}, {0.12f, 0.16f, 0.325f * k});   // torso 0.24 x 0.32
  part({0, 0, 0}, 0.f, {0.01f, 0, 1.63f * k}, {0.10f, 0.085f, 0.12f * k});  // head to 1.75 m
  for (float side : {1.f, -1.f}) {  // arms: shoulders at 1.45 m, outer faces at +-0.25 m
    part({0, side * 0.205f, 1.45f * k}, -0.45f * sw * side, {0, 0, -0.33f * k}, {0.045f, 0.045f, 0.33f * k});
  }
}

PeopleScene People::scene(double t, const Eigen::Vector2d& robot) const {
  PeopleScene sc;
  for (size_t i = 0; i < specs_.size(); ++i) {
    const PersonState st = state(i, t, robot);
    if (!st.present) continue;
    const size_t first = sc.boxes.size();
    addBody(st, specs_[i].height, sc.boxes);
    Eigen::AlignedBox3f bb;
    for (size_t b = first; b < sc.boxes.size(); ++b) {
      const OrientedBox& box = sc.boxes[b];
      const Eigen::Vector3f ext = box.rotation.cwiseAbs() * box.half;
      bb.extend(box.centre - ext);
      bb.extend(box.centre + ext);
    }
    sc.bounds.push_back(bb);
    sc.ranges.push_back({first, sc.boxes.size()});
  }
  return sc;
}

}  // namespace polyloc
