#include "protocol/dispatcher.hpp"

#include "protocol/messages.hpp"

#include <cmath>
#include <exception>

namespace polyloc::protocol {
namespace {

// Reply status for a pose: warnings say how far to trust it; none yet is NotAvailable.
Status poseStatus(const std::optional<PoseReport>& p) {
  if (!p || p->status == PoseStatus::Initialising) return Status::NotAvailable;
  if (p->status == PoseStatus::Uncertain) return Status::PoseUncertain;
  if (p->status == PoseStatus::Lost) return Status::PoseLost;
  return Status::Ok;
}

bool validSeed(const PoseSeed& s) {
  const auto sigmaOk = [](const std::optional<double>& v) { return !v || (std::isfinite(*v) && *v > 0); };
  return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.yaw) &&
         sigmaOk(s.sigma_xy_m) && sigmaOk(s.sigma_yaw_rad);
}

Frame checkProtocol(uint32_t command, WordSpan data) {
  const Words version{kProtocolVersion};
  if (data.size() > 1) return errorReply(command, Status::BadSize);
  if (data.empty()) return makeReply(command, Status::Ok, version);
  const uint32_t client = data[0];
  if (client >> 16 != kProtocolVersion >> 16) return makeReply(command, Status::VersionMismatch, version);
  const Status s = (client & 0xffff) > (kProtocolVersion & 0xffff) ? Status::NewerMinorVersion : Status::Ok;
  return makeReply(command, s, version);
}

Frame handle(const Frame& req, ControlHandler& h) {
  const uint32_t c = req.command;
  const WordSpan data = req.data;
  const auto sized = [&](size_t words) { return data.size() == words; };
  switch (c) {
    case cmd::PING: return makeReply(c, Status::Ok, data);
    case cmd::CHECKPROTOCOL: return checkProtocol(c, data);
    case cmd::GETPOSE:
    case cmd::GETPOSECOVARIANCE: {
      if (!sized(0)) return errorReply(c, Status::BadSize);
      const auto p = h.pose();
      const Status s = poseStatus(p);
      if (isError(s)) return errorReply(c, s);
      return makeReply(c, s, c == cmd::GETPOSE ? encodePlanarPose(*p) : encodePoseCovariance(*p));
    }
    case cmd::SETPOSE: {
      const auto seed = decodeSeed(data);
      if (!seed) return errorReply(c, Status::BadSize);
      if (!validSeed(*seed)) return errorReply(c, Status::BadArgument);
      return errorReply(c, h.setPose(*seed));
    }
    case cmd::GLOBALLOCALIZATION:
      if (!sized(0)) return errorReply(c, Status::BadSize);
      return errorReply(c, h.globalLocalization());
    case cmd::GETNUMSCANNERS:
      if (!sized(0)) return errorReply(c, Status::BadSize);
      return makeReply(c, Status::Ok, Words{static_cast<uint32_t>(h.scanners().size())});
    case cmd::GETSCANNERS:
      if (!sized(0)) return errorReply(c, Status::BadSize);
      return makeReply(c, Status::Ok, encodeScanners(h.scanners()));
    case cmd::GETSCANNERPOSE:
    case cmd::GETSCANRADIALSCANNER: {
      if (!sized(1)) return errorReply(c, Status::BadSize);
      const uint32_t index = data[0];
      const auto list = h.scanners();
      if (index >= list.size()) return errorReply(c, Status::BadArgument);
      if (c == cmd::GETSCANNERPOSE) return makeReply(c, Status::Ok, encodeMount(list[index].mount));
      const auto scan = h.scan(index);
      if (!scan) return errorReply(c, Status::NotAvailable);
      const Status s = index == 0 && !h.collisionAvoidance() ? Status::CollisionAvoidanceOff : Status::Ok;
      return makeReply(c, s, encodeScan(*scan));
    }
    case cmd::GETCOLLISIONAVOIDANCE:
      if (!sized(0)) return errorReply(c, Status::BadSize);
      return makeReply(c, Status::Ok, Words{h.collisionAvoidance() ? 1u : 0u});
    case cmd::SETCOLLISIONAVOIDANCE:
      if (!sized(1)) return errorReply(c, Status::BadSize);
      if (data[0] > 1) return errorReply(c, Status::BadArgument);
      h.setCollisionAvoidance(data[0] == 1);
      return errorReply(c, Status::Ok);
    case cmd::GETTRACKS:
      if (!sized(0)) return errorReply(c, Status::BadSize);
      return makeReply(c, Status::Ok, encodeTracks(h.tracks()));
    case cmd::GETSTATUS:
      if (!sized(0)) return errorReply(c, Status::BadSize);
      return makeReply(c, Status::Ok, encodeHealth(h.health()));
    default: return errorReply(c, Status::UnknownCommand);
  }
}

}  // namespace

Dispatched dispatch(const Frame& request, ControlHandler& handler) {
  try {
    return {handle(request, handler), {}};
  } catch (const std::exception& e) {
    return {errorReply(request.command, Status::Internal), e.what()};
  } catch (...) {
    return {errorReply(request.command, Status::Internal), "unknown exception"};
  }
}

}  // namespace polyloc::protocol
