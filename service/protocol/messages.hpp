// The data words of each command's request and reply (after the reply's status word), shared
// by the server's dispatcher and the client, so both ends agree by construction. Encodings
// (docs/protocol.md): lengths in metres, angles in radians, both IEEE binary32; stamps int64
// nanoseconds and counters uint64 as two words, low first; names as byte count + bytes.
// Decoders take exactly the words of one message and give nullopt when the size is wrong.
#pragma once

#include "protocol/handler.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace polyloc::protocol {

using Words = std::vector<uint32_t>;
using WordSpan = std::span<const uint32_t>;

// SETPOSE request: x y yaw [sigma_xy sigma_yaw] (3 or 5 words).
Words encodeSeed(const PoseSeed& seed);
std::optional<PoseSeed> decodeSeed(WordSpan data);

// GETPOSE reply: x y yaw stamp (planar, 5 words).
Words encodePlanarPose(const PoseReport& p);
std::optional<PoseReport> decodePlanarPose(WordSpan data);

// GETPOSECOVARIANCE reply: pose status, stamp, x y z roll pitch yaw, 36 covariance, ess,
// particles (47 words).
Words encodePoseCovariance(const PoseReport& p);
std::optional<PoseReport> decodePoseCovariance(WordSpan data);

// GETSCANNERPOSE reply: x y z roll pitch yaw of the mount (6 words).
Words encodeMount(const Pose& mount);
std::optional<Pose> decodeMount(WordSpan data);

// GETSCANNERS reply: count, then per scanner: mount (6), beams, name.
Words encodeScanners(const std::vector<ScannerInfo>& scanners);
std::optional<std::vector<ScannerInfo>> decodeScanners(WordSpan data);

// GETSCANRADIALSCANNER reply: stamp, count n, n x (angle, range).
Words encodeScan(const PolarScan& scan);
std::optional<PolarScan> decodeScan(WordSpan data);

// GETTRACKS reply: stamp, count, per track: id, confirmed, x y vx vy, covariance[4] (10 words).
Words encodeTracks(const TrackList& tracks);
std::optional<TrackList> decodeTracks(WordSpan data);

// GETSTATUS reply: stamp, uptime, pose status, cycles, poses, vrs, tracks, pose rate, cycle
// p50 and p99, input count, per input: rate, taken, rejected, silence, silent, name.
Words encodeHealth(const HealthReport& h);
std::optional<HealthReport> decodeHealth(WordSpan data);

}  // namespace polyloc::protocol
