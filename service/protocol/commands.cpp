#include "protocol/commands.hpp"

namespace polyloc::protocol {

const char* toString(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::PoseUncertain: return "pose_uncertain";
    case Status::PoseLost: return "pose_lost";
    case Status::NewerMinorVersion: return "newer_minor_version";
    case Status::CollisionAvoidanceOff: return "collision_avoidance_off";
    case Status::UnknownCommand: return "unknown_command";
    case Status::BadSize: return "bad_size";
    case Status::BadArgument: return "bad_argument";
    case Status::NotAvailable: return "not_available";
    case Status::VersionMismatch: return "version_mismatch";
    case Status::Internal: return "internal";
    case Status::Busy: return "busy";
    case Status::BadMagic: return "bad_magic";
    case Status::BadCrc: return "bad_crc";
    case Status::BadFrameSize: return "bad_frame_size";
    case Status::FrameTooLarge: return "frame_too_large";
    case Status::FrameTimeout: return "frame_timeout";
  }
  return isError(s) ? "unknown_error" : "unknown_warning";
}

const char* commandName(uint32_t command) {
  switch (command) {
    case cmd::PING: return "PING";
    case cmd::CHECKPROTOCOL: return "CHECKPROTOCOL";
    case cmd::GETPOSE: return "GETPOSE";
    case cmd::SETPOSE: return "SETPOSE";
    case cmd::GETNUMSCANNERS: return "GETNUMSCANNERS";
    case cmd::GETSCANNERPOSE: return "GETSCANNERPOSE";
    case cmd::GETSCANRADIALSCANNER: return "GETSCANRADIALSCANNER";
    case cmd::GETCOLLISIONAVOIDANCE: return "GETCOLLISIONAVOIDANCE";
    case cmd::SETCOLLISIONAVOIDANCE: return "SETCOLLISIONAVOIDANCE";
    case cmd::GLOBALLOCALIZATION: return "GLOBALLOCALIZATION";
    case cmd::GETPOSECOVARIANCE: return "GETPOSECOVARIANCE";
    case cmd::GETTRACKS: return "GETTRACKS";
    case cmd::GETSTATUS: return "GETSTATUS";
    case cmd::GETSCANNERS: return "GETSCANNERS";
    case cmd::FRAME_ERROR: return "FRAME_ERROR";
  }
  return nullptr;
}

}  // namespace polyloc::protocol
