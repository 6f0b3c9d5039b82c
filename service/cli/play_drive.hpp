// `polyloc play --drive` (play_drive.cpp) and the JSON of a closed-loop run, shared with eval nav.
#pragma once

#include <polyloc/sim/drive.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace polyloc::cli {

class DriveLoop;

struct PlayDriveArgs {
  std::string scenario, shm;
  double rate = 1, duration = 0, wait = 10, command_latency = 0.05;
  bool json = false, quiet = false;
};

void runPlayDrive(const PlayDriveArgs& a);
nlohmann::json collisionJson(const CollisionEvent& c);
nlohmann::json driveJson(const DriveLoop& loop);

}  // namespace polyloc::cli
