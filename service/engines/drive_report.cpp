#include "engines/drive_report.hpp"

#include "engines/drive_loop.hpp"

namespace polyloc::engines {

nlohmann::json collisionJson(const CollisionEvent& c) {
  return {{"t", c.t},
          {"what", c.contact.what},
          {"label", c.contact.label},
          {"where", {c.contact.where.x(), c.contact.where.y(), c.contact.where.z()}},
          {"pose", {c.pose.x(), c.pose.y(), c.pose.yaw()}}};
}

nlohmann::json driveJson(const DriveLoop& loop) {
  const DriveSim& d = loop.drive();
  const auto& b = d.base().counters();
  const auto& c = loop.counters();
  nlohmann::json collisions = nlohmann::json::array();
  for (const CollisionEvent& e : d.collisions()) collisions.push_back(collisionJson(e));
  const Pose p = d.truth();
  return {{"sim_s", d.nowS()},
          {"final_pose", {p.x(), p.y(), p.yaw()}},
          {"collisions", collisions},
          {"contacts", d.contacts()},
          {"struck_by_people", d.struckBy().size()},  // people walking into the robot: not its collisions
          {"base", {{"accepted", b.accepted}, {"rejected", b.rejected}, {"clamped", b.clamped},
                    {"timeouts", b.timeouts}, {"last_rejection", d.lastRejection()}}},
          {"loop", {{"steps", c.steps}, {"triggers", c.triggers}, {"vrs_missed", c.vrs_missed},
                    {"commands", c.commands}, {"commands_late", c.commands_late},
                    {"commands_rejected", c.commands_rejected}, {"last_command", loop.lastCommandStatus()},
                    {"reattached", c.reattached}, {"commands_since_attach", c.commands_since_attach}}}};
}

}  // namespace polyloc::engines
