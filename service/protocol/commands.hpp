// Command ids and reply status codes of the control protocol (docs/protocol.md is the spec).
// The mobiled ids are those of the earlier motion daemon, so its controllers work unchanged;
// polyloc's own commands live in 0x00100000..0x001fffff, away from any mobiled group.
#pragma once

#include <cstdint>

namespace polyloc::protocol {

// Protocol version: major << 16 | minor. A new minor only adds commands or trailing words.
inline constexpr uint32_t kProtocolVersion = 0x00010001;  // 1.1: GETSTATUS carries the map fit

namespace cmd {
inline constexpr uint32_t PING = 0x00000000;
inline constexpr uint32_t CHECKPROTOCOL = 0x00000001;
inline constexpr uint32_t GETPOSE = 0x00020000;
inline constexpr uint32_t SETPOSE = 0x00020001;
inline constexpr uint32_t GETNUMSCANNERS = 0x00040000;
inline constexpr uint32_t GETSCANNERPOSE = 0x00040001;
inline constexpr uint32_t GETSCANRADIALSCANNER = 0x00040002;
inline constexpr uint32_t GETCOLLISIONAVOIDANCE = 0x00050000;
inline constexpr uint32_t SETCOLLISIONAVOIDANCE = 0x00050001;

// polyloc's own range.
inline constexpr uint32_t kOwnFirst = 0x00100000;
inline constexpr uint32_t kOwnLast = 0x001fffff;
inline constexpr uint32_t GLOBALLOCALIZATION = 0x00100000;
inline constexpr uint32_t GETPOSECOVARIANCE = 0x00100001;
inline constexpr uint32_t GETTRACKS = 0x00100002;
inline constexpr uint32_t GETSTATUS = 0x00100003;
inline constexpr uint32_t GETSCANNERS = 0x00100004;

// Bit 31 marks a reply. A frame error (garbage, bad CRC, ...) is answered with FRAME_ERROR,
// because the command id of a broken frame cannot be trusted; 0x7fffffff is never a request.
inline constexpr uint32_t kReplyBit = 0x80000000u;
inline constexpr uint32_t FRAME_ERROR = 0xffffffffu;
}  // namespace cmd

inline constexpr uint32_t replyId(uint32_t command) { return command | cmd::kReplyBit; }

// First data word of every reply: 0 ok, > 0 warning (the data is valid but qualified),
// < 0 error (no data follows the status).
enum class Status : int32_t {
  Ok = 0,
  PoseUncertain = 1,          // the estimate is spread out (low ESS, wide covariance)
  PoseLost = 2,               // localisation lost; the pose is the last estimate
  NewerMinorVersion = 3,      // CHECKPROTOCOL: the client knows commands this server lacks
  CollisionAvoidanceOff = 4,  // the VRS (scan 0) while its publication is switched off

  UnknownCommand = -1,
  BadSize = -2,          // the request's data size is wrong for its command
  BadArgument = -3,      // a value out of range: scanner index, NaN in a pose, flag not 0/1
  NotAvailable = -4,     // not yet: no pose before initialisation, no scan received yet
  VersionMismatch = -5,  // CHECKPROTOCOL: another major version
  Internal = -6,         // the handler failed (logged on the server)
  Busy = -7,             // too many clients; the connection is closed after this reply

  // Frame errors, in a FRAME_ERROR reply.
  BadMagic = -16,  // bytes that are not the start of a frame (skipped)
  BadCrc = -17,
  BadFrameSize = -18,   // size field < 16 or not a multiple of 4
  FrameTooLarge = -19,  // size field over the server's limit
  FrameTimeout = -20,   // a frame was started and not completed in time; closed after this
};

inline constexpr bool isError(Status s) { return static_cast<int32_t>(s) < 0; }
const char* toString(Status s);             // "ok", "bad_crc", ...; "unknown_error"/"unknown_warning"
const char* commandName(uint32_t command);  // "GETPOSE", ...; nullptr for an unknown id

}  // namespace polyloc::protocol
