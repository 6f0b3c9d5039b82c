// The JSON of a closed-loop run (polyloc play --drive, polyloc eval nav): what the base did
// (commands taken, rejected, clamped), collisions with where and what, the loop's waits.
#pragma once

#include <polyloc/sim/drive.hpp>

#include <nlohmann/json.hpp>

namespace polyloc::engines {

class DriveLoop;

nlohmann::json collisionJson(const CollisionEvent& c);
nlohmann::json driveJson(const DriveLoop& loop);

}  // namespace polyloc::engines
