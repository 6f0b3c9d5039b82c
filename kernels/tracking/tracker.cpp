#include <polyloc/tracking/hungarian.hpp>
#include <polyloc/tracking/tracker.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace polyloc {

const char* trackStatusName(TrackStatus s) {
  switch (s) {
    case TrackStatus::Tentative: return "tentative";
    case TrackStatus::Confirmed: return "confirmed";
    case TrackStatus::Deleted: return "deleted";
  }
  return "?";
}

bool Tracks::inside(const Eigen::Vector2d& p, double sigmas, double radius) const {
  if (!p.allFinite() || !(sigmas > 0)) return false;
  for (const TrackState& t : items) {
    if (t.status != TrackStatus::Confirmed) continue;
    const Eigen::Matrix2d cov = t.position_cov + Eigen::Matrix2d::Identity() * (radius * radius / (sigmas * sigmas));
    const Eigen::Vector2d d = p - t.position;
    const Eigen::LDLT<Eigen::Matrix2d> ldlt(cov);
    if (ldlt.info() == Eigen::Success && d.dot(ldlt.solve(d)) <= sigmas * sigmas) return true;
  }
  return false;
}

size_t Tracks::confirmed() const {
  size_t n = 0;
  for (const TrackState& t : items) n += t.status == TrackStatus::Confirmed;
  return n;
}

MultiTargetTracker::MultiTargetTracker(const TrackerConfig& config) : c_(config) {}

void MultiTargetTracker::clear() {
  tracks_.clear();
  lost_.clear();
  snapshot_ = {};
  started_ = false;
}

TrackState MultiTargetTracker::stateOf(const Track& t) {
  TrackState s;
  s.id = t.id;
  s.status = t.status;
  s.position = t.kf.position();
  s.velocity = t.kf.velocity();
  s.position_cov = t.kf.positionCov();
  s.velocity_cov = t.kf.velocityCov();
  s.ellipse = covarianceEllipse(s.position_cov);
  s.first_ns = t.first_ns;
  s.last_detection_ns = t.last_detection_ns;
  s.hits = t.hits;
  return s;
}

void MultiTargetTracker::snapshot(int64_t stamp_ns, const std::vector<Track>& dropped) {
  snapshot_.stamp_ns = stamp_ns;
  snapshot_.items.clear();
  for (const Track& t : tracks_) snapshot_.items.push_back(stateOf(t));
  for (const Track& t : dropped) {
    snapshot_.items.push_back(stateOf(t));
    snapshot_.items.back().status = TrackStatus::Deleted;
  }
}

Tracks MultiTargetTracker::predicted(int64_t stamp_ns) const {
  Tracks out;
  out.stamp_ns = stamp_ns;
  for (Track t : tracks_) {
    t.kf.predict(double(stamp_ns - stamp_ns_) * 1e-9, c_.acceleration_sigma);
    out.items.push_back(stateOf(t));
  }
  return out;
}

// A newly confirmed track takes the id of the nearest confirmed track dropped lately whose
// position, moved on by its velocity, is within the search radius.
void MultiTargetTracker::revive(Track& t, int64_t stamp_ns) {
  if (c_.revive_time <= 0 || lost_.empty()) return;
  size_t best = lost_.size();
  double best_d = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < lost_.size(); ++k) {
    const double gone = double(stamp_ns - lost_[k].stamp_ns) * 1e-9;
    const double d = (lost_[k].position + lost_[k].velocity * gone - t.kf.position()).norm();
    if (d <= c_.revive_distance + c_.revive_speed * gone && d < best_d) best = k, best_d = d;
  }
  if (best == lost_.size()) return;
  t.id = lost_[best].id;
  lost_.erase(lost_.begin() + ptrdiff_t(best));
}

bool MultiTargetTracker::update(int64_t stamp_ns, std::span<const Detection> detections, const VisibilityFn& seen) {
  if (started_ && stamp_ns < stamp_ns_) return false;
  const double dt = started_ ? double(stamp_ns - stamp_ns_) * 1e-9 : 0.0;
  started_ = true;
  stamp_ns_ = stamp_ns;
  for (Track& t : tracks_) t.kf.predict(dt, c_.acceleration_sigma);

  std::vector<const Detection*> dets;
  for (const Detection& d : detections)
    if (d.position.allFinite()) dets.push_back(&d);
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * c_.measurement_sigma * c_.measurement_sigma;

  // Cost of a pair inside the gate: its negative log-likelihood (Mahalanobis distance squared
  // plus the log-determinant, so an uncertain track does not win every detection near it).
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd cost(Eigen::Index(tracks_.size()), Eigen::Index(dets.size()));
  for (size_t i = 0; i < tracks_.size(); ++i)
    for (size_t j = 0; j < dets.size(); ++j) {
      const double m2 = tracks_[i].kf.mahalanobis2(dets[j]->position, R);
      cost(Eigen::Index(i), Eigen::Index(j)) =
          m2 <= c_.gate * c_.gate ? m2 + std::log(tracks_[i].kf.innovation(R).determinant()) : inf;
    }
  const std::vector<int> match = solveAssignment(cost);

  std::vector<char> used(dets.size(), 0);
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (match[i] < 0) continue;
    Track& t = tracks_[i];
    t.kf.update(dets[size_t(match[i])]->position, R);
    t.kf.clampSpeed(c_.max_speed);
    t.last_detection_ns = t.not_empty_ns = stamp_ns;
    ++t.hits;
    used[size_t(match[i])] = 1;
    if (t.status == TrackStatus::Tentative && t.hits >= uint32_t(c_.confirm_hits) &&
        (t.kf.position() - t.origin).norm() >= c_.confirm_distance) {
      t.status = TrackStatus::Confirmed;
      revive(t, stamp_ns);
    }
  }

  std::vector<Track> dropped, live;
  for (Track& t : tracks_) {
    const Visibility v = seen && t.last_detection_ns != stamp_ns ? seen(t.kf.position()) : Visibility::Unknown;
    if (v != Visibility::Empty) t.not_empty_ns = stamp_ns;
    const double idle = double(stamp_ns - t.last_detection_ns) * 1e-9;
    const double empty = double(stamp_ns - t.not_empty_ns) * 1e-9;
    const double age = double(stamp_ns - t.first_ns) * 1e-9;
    const double sigma = std::sqrt(std::max(0.0, t.kf.positionCov().eigenvalues().real().maxCoeff()));
    const bool unconfirmed = t.status == TrackStatus::Tentative && age > c_.confirm_time;
    if (idle > c_.timeout || empty > c_.empty_timeout || sigma > c_.max_sigma || unconfirmed) dropped.push_back(t);
    else live.push_back(t);
  }
  tracks_ = std::move(live);
  for (const Track& t : dropped)
    if (t.status == TrackStatus::Confirmed && c_.revive_time > 0)
      lost_.push_back({t.id, t.kf.position(), t.kf.velocity(), stamp_ns});
  std::erase_if(lost_, [&](const Lost& l) { return double(stamp_ns - l.stamp_ns) * 1e-9 > c_.revive_time; });

  // Unassigned detections start tracks, except next to a confirmed one: that is the person's
  // other leg or a second scanner's view of the same person, not a new person.
  for (size_t j = 0; j < dets.size(); ++j) {
    if (used[j]) continue;
    bool near = false;
    for (const Track& t : tracks_)
      near = near || (t.status == TrackStatus::Confirmed &&
                      (t.kf.position() - dets[j]->position).norm() < c_.new_track_distance);
    if (near) continue;
    Track t;
    t.id = next_id_++;
    t.kf = ConstantVelocityKalman::start(dets[j]->position, R, c_.init_speed_sigma);
    t.first_ns = t.last_detection_ns = t.not_empty_ns = stamp_ns;
    t.hits = 1;
    t.origin = dets[j]->position;
    if (c_.confirm_hits <= 1 && c_.confirm_distance <= 0) t.status = TrackStatus::Confirmed;
    tracks_.push_back(t);
  }
  snapshot(stamp_ns, dropped);
  return true;
}

}  // namespace polyloc
