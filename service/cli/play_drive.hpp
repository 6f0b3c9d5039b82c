// `polyloc play --drive` (play_drive.cpp): the scenario's robot driven by a controller's commands.
#pragma once

#include <string>

namespace polyloc::cli {

struct PlayDriveArgs {
  std::string scenario, shm;
  double rate = 1, duration = 0, wait = 10, command_latency = 0.05;
  bool json = false, quiet = false;
};

void runPlayDrive(const PlayDriveArgs& a);

}  // namespace polyloc::cli
