#include "engines/nav_missions.hpp"

#include "engines/drive_report.hpp"

#include <polyloc_shm.h>

#include <cmath>

namespace polyloc::engines {

MissionTracker::MissionTracker(const polynav::Zones& zones, std::vector<polynav::GoalSpot> goals,
                               polynav::Polygon footprint, OptimalLength optimal)
    : zones_(zones), goals_(std::move(goals)), footprint_(std::move(footprint)), optimal_(std::move(optimal)) {
  results_.resize(goals_.size());
  for (size_t i = 0; i < goals_.size(); ++i) results_[i].goal = goals_[i].name;
}

MissionResult* MissionTracker::active() {
  return current_ < results_.size() && results_[current_].started && !results_[current_].ended ? &results_[current_] : nullptr;
}

void MissionTracker::onCommand(uint32_t goal, uint32_t state, const std::string& status, double t, const Pose& truth) {
  if (goal >= results_.size()) {
    if (active()) abort(t, "the controller moved on without ending it");
    current_ = results_.size();
    return;
  }
  if (goal > current_ && active()) {
    if (active()->settling) settle(*active(), truth);  // moved on while the base still braked
    else abort(t, "the controller moved on without ending it");
  }
  if (goal < current_) return;  // late frames of an ended mission
  current_ = goal;
  MissionResult& m = results_[goal];
  if (!m.started) {
    m.started = true;
    m.t_start = t;
    if (optimal_) m.optimal_m = optimal_({truth.x(), truth.y()}, goals_[goal]);
  }
  if (m.ended || m.settling || (state != POLYLOC_NAV_REACHED && state != POLYLOC_NAV_FAILED)) return;
  m.settling = true;  // ended when the base stands (onStep)
  m.t_end = t;
  m.reached = state == POLYLOC_NAV_REACHED;
  m.end_status = status;
}

void MissionTracker::settle(MissionResult& m, const Pose& truth) {
  const Eigen::Vector3d& g = goals_[size_t(&m - results_.data())].pose;
  m.goal_error_m = std::hypot(truth.x() - g.x(), truth.y() - g.y());
  m.goal_yaw_error_deg = std::abs(std::remainder(truth.yaw() - g.z(), 2 * M_PI)) * 180 / M_PI;
  m.settling = false;
  m.ended = true;
}

void MissionTracker::abort(double t, const std::string& why) {
  MissionResult* m = active();
  if (!m) return;
  if (m->settling) {  // the controller had ended it: its verdict stands, scored where the robot is
    if (last_) settle(*m, *last_);
    else m->settling = false, m->ended = true;
    return;
  }
  m->ended = true;
  m->t_end = t;
  m->end_status = why;
}

void MissionTracker::onStep(const Pose& truth, double forward_speed, double turn_rate, double clearance) {
  const Eigen::Vector2d p(truth.x(), truth.y());
  MissionResult* m = active();
  if (m && m->settling && std::abs(forward_speed) < 1e-3 && std::abs(turn_rate) < 1e-3) {
    settle(*m, truth);
    m = nullptr;
  }
  if (m && last_) m->driven_m += std::hypot(truth.x() - last_->x(), truth.y() - last_->y());
  last_ = truth;
  if (m) m->min_clearance_m = std::min(m->min_clearance_m, clearance);
  const bool danger = !zones_.danger.empty() && zones_.inDanger(footprint_, {truth.x(), truth.y(), truth.yaw()});
  if (danger && !in_danger_ && m) ++m->danger_entries;
  in_danger_ = danger;
  // Door passages: from entering a door region to leaving it; a change of the driving direction
  // inside is an oscillation (the base's speed, ignoring creeping below 2 cm/s).
  const std::optional<size_t> d = zones_.doorAt(p);
  if (d != door_) {
    if (door_ && m) {
      ++m->door_passages;
      if (door_reversals_ > 0) ++m->door_oscillations;
    }
    door_ = d, door_sign_ = 0, door_reversals_ = 0;
  }
  if (door_ && std::abs(forward_speed) > 0.02) {
    const int s = forward_speed > 0 ? 1 : -1;
    if (door_sign_ && s != door_sign_) ++door_reversals_;
    door_sign_ = s;
  }
}

void MissionTracker::onCollision(const CollisionEvent& c) {
  if (MissionResult* m = active()) m->collisions.push_back(c);
  else if (current_ < results_.size()) results_[current_].collisions.push_back(c);
}

bool MissionTracker::done() const { return results_.empty() || current_ >= results_.size() || (current_ + 1 == results_.size() && results_.back().ended); }

nlohmann::json MissionTracker::json() const {
  nlohmann::json out = nlohmann::json::array();
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  for (const MissionResult& m : results_) {
    nlohmann::json c = nlohmann::json::array();
    for (const CollisionEvent& e : m.collisions) c.push_back(collisionJson(e));
    out.push_back({{"goal", m.goal}, {"reached", m.reached}, {"ended", m.ended}, {"status", m.end_status},
                   {"t_start", m.t_start}, {"duration_s", m.ended ? num(m.duration()) : nlohmann::json(nullptr)},
                   {"goal_error_m", num(m.goal_error_m)}, {"goal_yaw_error_deg", num(m.goal_yaw_error_deg)},
                   {"collisions", c}, {"min_clearance_m", num(m.min_clearance_m)}, {"danger_entries", m.danger_entries},
                   {"door_passages", m.door_passages}, {"door_oscillations", m.door_oscillations},
                   {"driven_m", m.driven_m}, {"optimal_m", num(m.optimal_m)}});
  }
  return out;
}

}  // namespace polyloc::engines
