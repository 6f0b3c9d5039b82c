#include <polyloc/io/message_pose.hpp>

namespace polyloc {

msg::Pose toMsgPose(const Pose& p) {
  msg::Pose m;
  m.position = {p.x(), p.y(), p.z()};
  const Eigen::Quaterniond& q = p.rotation();
  m.orientation = {q.x(), q.y(), q.z(), q.w()};
  return m;
}

Pose fromMsgPose(const msg::Pose& m) {
  const auto& q = m.orientation;
  return Pose(Eigen::Quaterniond(q.w, q.x, q.y, q.z), Eigen::Vector3d(m.position.x, m.position.y, m.position.z));
}

msg::Transform toMsgTransform(const Pose& p) {
  msg::Transform t;
  t.translation = {p.x(), p.y(), p.z()};
  const Eigen::Quaterniond& q = p.rotation();
  t.rotation = {q.x(), q.y(), q.z(), q.w()};
  return t;
}

}  // namespace polyloc
