// Poses to and from message fields (geometry_msgs/Pose, Transform): REP-103 quaternion order.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/messages.hpp>

namespace polyloc {

msg::Pose toMsgPose(const Pose& p);
Pose fromMsgPose(const msg::Pose& m);
msg::Transform toMsgTransform(const Pose& p);

}  // namespace polyloc
