#include <polyloc/tracking/motion_detector.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

std::shared_ptr<StaticMemory> sharedStaticMemory(const MotionConfig& c) {
  return std::make_shared<StaticMemory>(c.static_cell, c.static_time, c.static_gap);
}

const char* scanCheckName(ScanCheck c) {
  switch (c) {
    case ScanCheck::Ok: return "ok";
    case ScanCheck::WrongSize: return "wrong number of ranges";
    case ScanCheck::BadPose: return "pose not finite";
    case ScanCheck::OutOfOrder: return "stamp not after the previous scan";
  }
  return "?";
}

MotionDetector::MotionDetector(const PlanarScannerSpec& spec, const MotionConfig& config,
                               std::shared_ptr<StaticMemory> memory)
    : spec_(spec), c_(config), beams_(spec.numBeams()), angle_min_(spec.angleMin()),
      static_(memory ? std::move(memory) : sharedStaticMemory(config)) {
  if (c_.reference_ages.empty()) throw std::invalid_argument("motion detection needs at least one reference age");
  for (double a : c_.reference_ages)
    if (!(a > 0)) throw std::invalid_argument("motion detection: reference ages must be > 0 s");
  if (!(c_.margin >= 0) || !(c_.margin_per_m >= 0)) throw std::invalid_argument("motion detection: margins must be >= 0");
  if (!(spec_.resolution_rad > 0) || beams_ == 0) throw std::invalid_argument("motion detection: scanner without beams");
  for (size_t i = 0; i < beams_; ++i) {
    const double a = angle_min_ + double(i) * spec_.resolution_rad;
    cos_.push_back(std::cos(a)), sin_.push_back(std::sin(a));
  }
}

// Where p lies for scan s: in its free space (every beam of the window passed p by the margin),
// on what it saw (a beam of the window ended within the margin of p), behind what it saw, or
// unknown (outside the field of view, an invalid beam in the window).
MotionDetector::Seen MotionDetector::classify(const Scan& s, const Eigen::Vector3d& p, int* beam, double* dist,
                                              double margin, double extra_rad) const {
  const Eigen::Vector3d q = s.sensor_T_map * p;
  const double d = std::hypot(q.x(), q.y());
  if (!(d > 1e-6)) return Seen::Unknown;
  const long k = std::lround((std::atan2(q.y(), q.x()) - angle_min_) / spec_.resolution_rad);
  if (k < 0 || k >= long(beams_)) return Seen::Unknown;
  const double m = margin >= 0 ? margin : c_.margin + c_.margin_per_m * d;
  // The window covers the margin sideways too: a pose or bearing error moves edges that much.
  const long w = std::clamp(long(std::ceil((std::atan2(m, d) + extra_rad) / spec_.resolution_rad)),
                            long(c_.window_beams), 50L);
  if (k - w < 0 || k + w >= long(beams_)) return Seen::Unknown;
  if (beam) *beam = int(k);
  if (dist) *dist = d;
  double nearest = std::numeric_limits<double>::infinity();
  bool hit = false;
  for (long j = k - w; j <= k + w; ++j) {
    const float r = s.free[size_t(j)];
    if (std::isnan(r)) return Seen::Unknown;
    nearest = std::min(nearest, double(r));
    hit = hit || std::abs(double(r) - d) <= m;
  }
  if (nearest > d + m) return Seen::Free;
  return hit ? Seen::Hit : Seen::Occluded;
}

MotionDetector::Look MotionDetector::look(const Eigen::Vector2d& p, double radius) const {
  if (history_.empty() || !p.allFinite()) return Look::Hidden;
  const Scan& s = history_.back();
  const Eigen::Vector3d q(p.x(), p.y(), s.map_T_sensor.z());
  if ((q - s.map_T_sensor.translation()).head<2>().norm() > c_.max_range) return Look::Hidden;
  switch (classify(s, q, nullptr, nullptr, radius)) {
    case Seen::Free: return Look::Empty;
    case Seen::Hit: return Look::Occupied;
    default: return Look::Hidden;
  }
}

std::vector<const MotionDetector::Scan*> MotionDetector::references(int64_t stamp_ns) const {
  std::vector<const Scan*> out;
  for (double age : c_.reference_ages) {
    const int64_t target = stamp_ns - std::llround(age * 1e9);
    const Scan* best = nullptr;
    for (const Scan& s : history_)
      if (!best || std::llabs(s.stamp_ns - target) < std::llabs(best->stamp_ns - target)) best = &s;
    if (best && std::find(out.begin(), out.end(), best) == out.end()) out.push_back(best);
  }
  std::sort(out.begin(), out.end(), [](const Scan* a, const Scan* b) { return a->stamp_ns < b->stamp_ns; });
  return out;
}

MotionDetector::Scan MotionDetector::makeScan(int64_t stamp_ns, const Pose& map_T_sensor, std::span<const float> ranges) {
  Scan cur;
  cur.stamp_ns = stamp_ns;
  cur.map_T_sensor = map_T_sensor;
  cur.sensor_T_map = map_T_sensor.inverse();
  cur.free.resize(beams_);
  cur.ends.assign(beams_, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const float rmax = float(spec_.range_max);
  const double near = std::max(c_.min_range, spec_.range_min);
  for (size_t i = 0; i < beams_; ++i) {
    const float r = ranges[i];
    if (std::isnan(r) || r < float(spec_.range_min)) {
      ++counters_.invalid_ranges;
      cur.free[i] = std::numeric_limits<float>::quiet_NaN();
      continue;
    }
    // +inf and "no echo" at exactly range_max: free as far as the scanner reaches, no endpoint.
    if (r >= rmax) {
      cur.free[i] = rmax;
      continue;
    }
    cur.free[i] = r;
    if (r >= near && r <= c_.max_range) cur.ends[i] = map_T_sensor * Eigen::Vector3d(r * cos_[i], r * sin_[i], 0.0);
  }
  return cur;
}

MotionDetector::Marks MotionDetector::appeared(const Scan& cur, const std::vector<const Scan*>& refs) const {
  Marks m;
  m.moved.assign(beams_, 0);
  m.seen_since.assign(beams_, cur.stamp_ns);
  std::vector<double> widen;  // extra angular window per reference: heading error grows with motion
  for (const Scan* r : refs)
    widen.push_back(c_.turn_margin * std::abs(angleDiff(cur.map_T_sensor.yaw(), r->map_T_sensor.yaw())) +
                    c_.travel_margin * (cur.map_T_sensor.translation() - r->map_T_sensor.translation()).head<2>().norm());
  for (size_t i = 0; i < beams_; ++i) {
    if (!cur.ends[i].allFinite()) continue;
    ++m.compared;
    // Oldest reference first: the point moved in if it was free space and, once something was
    // there, stayed there. Free again after a hit means it comes and goes: a surface that the
    // scan plane grazes, not an object that arrived.
    bool free = false, hit = false, flicker = false;
    for (size_t k = 0; k < refs.size(); ++k) {
      const Seen s = classify(*refs[k], cur.ends[i], nullptr, nullptr, -1, widen[k]);
      if (s == Seen::Free) flicker = flicker || hit, free = true;
      if (s == Seen::Hit) hit = true, m.seen_since[i] = std::min(m.seen_since[i], refs[k]->stamp_ns);
    }
    m.moved[i] = free && !flicker;
  }
  return m;
}

void MotionDetector::receded(const Scan& cur, const std::vector<const Scan*>& refs, Marks& m) const {
  for (const Scan* r : refs) {
    const double reach = std::min(c_.recede_max, c_.max_speed * double(cur.stamp_ns - r->stamp_ns) * 1e-9);
    for (const Eigen::Vector3d& e : r->ends) {
      if (!e.allFinite() || static_->isStatic(e.head<2>(), cur.stamp_ns)) continue;
      int k = -1;
      double d = 0;
      if (classify(cur, e, &k, &d) != Seen::Free) continue;  // the beam now passes where r's ended
      const size_t j = size_t(k);
      // Already there when the reference was taken: something static that the vacated point
      // hid at times (a board the scan plane grazes in front of a panel), not the object.
      if (m.moved[j] || m.seen_since[j] <= r->stamp_ns || !cur.ends[j].allFinite()) continue;
      if (double(cur.free[j]) - d > reach) continue;
      // ... and the reference must have been blind there because of what it saw in front (the
      // object itself); a point it could not see at all (outside its field of view) says nothing.
      if (classify(*r, cur.ends[j], nullptr, nullptr) == Seen::Occluded) m.moved[j] = 1;
    }
  }
}

void MotionDetector::grow(const Scan& cur, const std::vector<const Scan*>& refs, const Marks& m,
                          std::vector<MotionPoint>& out) const {
  if (!(c_.grow_distance > 0) || refs.empty()) return;
  const Eigen::Vector2d origin = cur.map_T_sensor.translation().head<2>();
  const int64_t oldest = refs.front()->stamp_ns;
  for (size_t j = 0; j < beams_; ++j) {
    if (m.moved[j] || !cur.ends[j].allFinite() || m.seen_since[j] <= oldest) continue;
    const long w = long(std::ceil(std::atan2(c_.grow_distance, double(cur.free[j])) / spec_.resolution_rad)) + 1;
    bool near_seed = false;
    for (long i = std::max(0L, long(j) - w); i <= std::min(long(beams_) - 1, long(j) + w) && !near_seed; ++i)
      near_seed = m.moved[size_t(i)] && (cur.ends[size_t(i)] - cur.ends[j]).head<2>().norm() <= c_.grow_distance;
    if (near_seed && !static_->isStatic(cur.ends[j].head<2>(), cur.stamp_ns))
      out.push_back({cur.ends[j].head<2>(), origin, false});
  }
}

ScanCheck MotionDetector::detect(int64_t stamp_ns, const Pose& map_T_sensor, std::span<const float> ranges,
                                 std::vector<MotionPoint>& out) {
  ScanCheck check = ScanCheck::Ok;
  if (ranges.size() != beams_) check = ScanCheck::WrongSize;
  else if (!map_T_sensor.translation().allFinite() || !map_T_sensor.rotation().coeffs().allFinite())
    check = ScanCheck::BadPose;
  else if (!history_.empty() && stamp_ns <= history_.back().stamp_ns) check = ScanCheck::OutOfOrder;
  if (check != ScanCheck::Ok) {
    ++counters_.rejected;
    return check;
  }
  ++counters_.scans;
  Scan cur = makeScan(stamp_ns, map_T_sensor, ranges);
  if (!history_.empty()) {
    const Pose step = history_.back().sensor_T_map * map_T_sensor;
    if (step.translation().norm() > c_.jump_distance ||
        Eigen::AngleAxisd(step.rotation()).angle() > c_.jump_angle) {
      ++counters_.pose_jumps;
      history_.clear();
    }
  }
  const std::vector<const Scan*> refs = references(stamp_ns);
  Marks m = appeared(cur, refs);
  receded(cur, refs, m);
  for (size_t i = 0; i < beams_; ++i)
    if (m.moved[i] && static_->isStatic(cur.ends[i].head<2>(), stamp_ns)) m.moved[i] = 0;
  const size_t n_moved = size_t(std::count(m.moved.begin(), m.moved.end(), 1));
  if (m.compared > 0 && double(n_moved) > c_.max_moved_fraction * double(m.compared)) {
    ++counters_.pose_jumps;  // the references no longer fit the pose: start over from this scan
    history_.clear();
  } else {
    counters_.moved_points += n_moved;
    const Eigen::Vector2d origin = map_T_sensor.translation().head<2>();
    for (size_t i = 0; i < beams_; ++i)
      if (m.moved[i]) out.push_back({cur.ends[i].head<2>(), origin, true});
    grow(cur, refs, m, out);
  }
  for (size_t i = 0; i < beams_; ++i)
    if (cur.ends[i].allFinite()) static_->hit(cur.ends[i].head<2>(), stamp_ns);
  if (counters_.scans % 32 == 0) static_->forget(stamp_ns);
  history_.push_back(std::move(cur));
  const double keep = *std::max_element(c_.reference_ages.begin(), c_.reference_ages.end()) * 1.25 + 0.1;
  while (history_.size() > 1 && double(stamp_ns - history_.front().stamp_ns) * 1e-9 > keep) history_.pop_front();
  return ScanCheck::Ok;
}

}  // namespace polyloc
