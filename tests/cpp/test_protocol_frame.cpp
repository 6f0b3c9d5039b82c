// The frame codec and the data words of every message: known bytes, CRC vectors, round trips.
#include "protocol/frame.hpp"
#include "protocol/messages.hpp"
#include "protocol/words.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_protocol_frame {

using namespace polyloc;
using namespace polyloc::protocol;


std::vector<uint8_t> bytes(std::initializer_list<int> v) { return {v.begin(), v.end()}; }


TEST(ProtocolFrame, Crc32KnownVectors) {
  const char* check = "123456789";  // the CRC-32 check value of every catalogue
  EXPECT_EQ(crc32({reinterpret_cast<const uint8_t*>(check), 9}), 0xcbf43926u);
  EXPECT_EQ(crc32({}), 0u);
  // The first 12 bytes of a PING frame, CRC from Python's zlib.crc32.
  const auto head = bytes({0x48, 0x45, 0x4c, 0x4f, 0x10, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_EQ(crc32(head), 0x13b3a81fu);
}

TEST(ProtocolFrame, PingBytesAsOnTheWire) {
  EXPECT_EQ(encodeFrame(cmd::PING), bytes({0x48, 0x45, 0x4c, 0x4f, 0x10, 0, 0, 0, 0, 0, 0, 0, 0x1f, 0xa8, 0xb3, 0x13}));
}

TEST(ProtocolFrame, GetPoseReplyBytes) {
  // Status 0, x 1.25, y -2.5, yaw 0.5 (binary32), stamp 1700000000123456789 ns; from Python.
  PoseReport p;
  p.pose = Pose::planar(1.25, -2.5, 0.5);
  p.stamp_ns = 1700000000123456789;
  const Frame reply = makeReply(cmd::GETPOSE, Status::Ok, encodePlanarPose(p));
  EXPECT_EQ(reply.command, 0x80020000u);
  EXPECT_EQ(encodeFrame(reply), bytes({0x48, 0x45, 0x4c, 0x4f, 0x28, 0,    0,    0,    0,    0,    0x02, 0x80, 0, 0,
                                       0,    0,    0,    0,    0xa0, 0x3f, 0,    0,    0x20, 0xc0, 0,    0,    0, 0x3f,
                                       0x15, 0xcd, 0x85, 0x3d, 0xfe, 0x9c, 0x97, 0x17, 0x7d, 0x1e, 0x87, 0xa1}));
}

TEST(ProtocolFrame, SizeIsTheWholeFrameAndCrcCoversAllBeforeIt) {
  const std::vector<uint32_t> data{1, 2, 0xdeadbeef};
  const auto f = encodeFrame(0x00100003, data);
  ASSERT_EQ(f.size(), frameBytes(3));
  EXPECT_EQ(loadLE32(f.data()), kMagic);
  EXPECT_EQ(loadLE32(f.data() + 4), 28u);
  EXPECT_EQ(loadLE32(f.data() + 8), 0x00100003u);
  EXPECT_EQ(loadLE32(f.data() + 20), 0xdeadbeefu);
  EXPECT_EQ(loadLE32(f.data() + 24), crc32({f.data(), 24}));
}

TEST(ProtocolFrame, ReplyCarriesStatusFirst) {
  const Frame r = makeReply(cmd::GETNUMSCANNERS, Status::NotAvailable);
  EXPECT_EQ(r.command, cmd::GETNUMSCANNERS | cmd::kReplyBit);
  EXPECT_EQ(replyStatus(r), Status::NotAvailable);
  EXPECT_EQ(int32_t(r.data[0]), -4);
  EXPECT_TRUE(replyData(r).empty());
  EXPECT_EQ(replyStatus(Frame{0x80000000u, {}}), Status::BadSize);  // no status word: not a reply
  const Frame e = frameErrorReply(Status::BadCrc, 0x00020000);
  EXPECT_EQ(e.command, 0xffffffffu);
  EXPECT_EQ(e.data, (std::vector<uint32_t>{uint32_t(-17), 0x00020000}));
}

TEST(ProtocolWords, ValuesAndStrings) {
  WordWriter w;
  w.f32(1.5), w.i32(-3), w.i64(-2), w.u64(0x0123456789abcdefull), w.str("front"), w.str("");
  const auto words = w.words();
  ASSERT_EQ(words.size(), 1u + 1 + 2 + 2 + 3 + 1);
  EXPECT_EQ(words[0], 0x3fc00000u);
  EXPECT_EQ(words[4], 0x89abcdefu);  // low word first
  EXPECT_EQ(words[6], 5u);
  EXPECT_EQ(words[7], 0x6e6f7266u);  // "fron" in wire order
  WordReader r(words);
  EXPECT_EQ(r.f32(), 1.5f);
  EXPECT_EQ(r.i32(), -3);
  EXPECT_EQ(r.i64(), -2);
  EXPECT_EQ(r.u64(), 0x0123456789abcdefull);
  EXPECT_EQ(r.str(), "front");
  EXPECT_EQ(r.str(), "");
  EXPECT_TRUE(r.done());
  r.u32();
  EXPECT_FALSE(r.ok());                        // past the end
  const std::vector<uint32_t> lying{1000, 0};  // a string longer than the words left
  WordReader l(lying);
  EXPECT_EQ(l.str(), "");
  EXPECT_FALSE(l.ok());
}

TEST(ProtocolMessages, SeedRoundTripWithAndWithoutSpread) {
  PoseSeed s{1.5, -2.0, 0.75, 0.2, 0.1};
  auto d = decodeSeed(encodeSeed(s));
  ASSERT_TRUE(d);
  EXPECT_NEAR(d->x, 1.5, 1e-6);
  EXPECT_NEAR(d->yaw, 0.75, 1e-6);
  EXPECT_NEAR(*d->sigma_xy_m, 0.2, 1e-6);
  EXPECT_NEAR(*d->sigma_yaw_rad, 0.1, 1e-6);
  EXPECT_EQ(encodeSeed({1, 2, 3, {}, {}}).size(), 3u);
  d = decodeSeed(encodeSeed({1, 2, 3, {}, {}}));
  ASSERT_TRUE(d);
  EXPECT_FALSE(d->sigma_xy_m || d->sigma_yaw_rad);
  EXPECT_FALSE(decodeSeed(std::vector<uint32_t>(4)));
}

TEST(ProtocolMessages, PoseCovarianceRoundTrip) {
  PoseReport p;
  p.stamp_ns = -5;
  p.pose = Pose::fromXYZRPY(1, 2, 0.1, 0.01, -0.02, 2.5);
  for (int i = 0; i < 36; ++i) p.covariance(i / 6, i % 6) = 0.001 * i;
  p.status = PoseStatus::Uncertain, p.ess = 99.5, p.particles = 5000;
  const auto words = encodePoseCovariance(p);
  EXPECT_EQ(words.size(), 47u);
  const auto d = decodePoseCovariance(words);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->stamp_ns, -5);
  EXPECT_TRUE(d->pose.isApprox(p.pose, 1e-6));
  EXPECT_NEAR(d->covariance(5, 4), 0.001 * 34, 1e-7);
  EXPECT_EQ(d->status, PoseStatus::Uncertain);
  EXPECT_EQ(d->particles, 5000u);
  EXPECT_FALSE(decodePoseCovariance(WordSpan(words).first(46)));
  auto bad = words;
  bad[0] = 9;  // no such pose status
  EXPECT_FALSE(decodePoseCovariance(bad));
}

TEST(ProtocolMessages, ScanScannersTracksHealthRoundTrip) {
  PolarScan s{77, {-1.0f, 0.0f, 1.0f}, {2.0f, std::numeric_limits<float>::quiet_NaN(), -1.0f}};
  const auto ds = decodeScan(encodeScan(s));
  ASSERT_TRUE(ds);
  EXPECT_EQ(ds->stamp_ns, 77);
  EXPECT_EQ(ds->angles, s.angles);
  EXPECT_EQ(ds->ranges[0], 2.0f);
  EXPECT_TRUE(std::isinf(ds->ranges[1]) && std::isinf(ds->ranges[2]));  // no return: +inf

  const std::vector<ScannerInfo> sc{{"vrs", Pose(), 360},
                                    {"front_laser", Pose::fromXYZRPY(0.3, 0, 0.2, 0, 0.1, 0), 541}};
  const auto dsc = decodeScanners(encodeScanners(sc));
  ASSERT_TRUE(dsc && dsc->size() == 2);
  EXPECT_EQ((*dsc)[1].name, "front_laser");
  EXPECT_EQ((*dsc)[1].beams, 541u);
  EXPECT_TRUE((*dsc)[1].mount.isApprox(sc[1].mount, 1e-6));

  TrackList t{9, {{3, true, 1, 2, 3, 4, {1, 0, 0, 1}}}};
  const auto dt = decodeTracks(encodeTracks(t));
  ASSERT_TRUE(dt && dt->tracks.size() == 1);
  EXPECT_EQ(dt->tracks[0].id, 3u);
  EXPECT_TRUE(dt->tracks[0].confirmed);
  EXPECT_EQ(dt->tracks[0].vy, 4.0);

  HealthReport h;
  h.cycles = 1ull << 40;
  h.inputs.push_back({"scan/front", 10, 1, 2, 0.5, true, 0.875});
  h.unfit = true;
  const Words words = encodeHealth(h);
  const auto dh = decodeHealth(words);
  ASSERT_TRUE(dh && dh->inputs.size() == 1);
  EXPECT_EQ(dh->cycles, 1ull << 40);
  EXPECT_EQ(dh->inputs[0].name, "scan/front");
  EXPECT_TRUE(dh->inputs[0].silent);
  EXPECT_EQ(dh->inputs[0].map_fit, 0.875);
  EXPECT_TRUE(dh->unfit);
  // A 1.0 server's reply (no map fit after the inputs) still decodes: fit not measured.
  const auto old = decodeHealth(WordSpan(words).first(words.size() - 2));
  ASSERT_TRUE(old && old->inputs.size() == 1);
  EXPECT_EQ(old->inputs[0].map_fit, -1);
  EXPECT_FALSE(old->unfit);
}

TEST(ProtocolMessages, CorruptCountsAreRejectedWithoutAllocating) {
  // A count of 2^32-1 entries in a reply of a few words: refused, not a 100 GB vector.
  EXPECT_FALSE(decodeScan(std::vector<uint32_t>{0, 0, 0xffffffffu, 0, 0}));
  EXPECT_FALSE(decodeTracks(std::vector<uint32_t>{0, 0, 0xffffffffu}));
  EXPECT_FALSE(decodeScanners(std::vector<uint32_t>{0xffffffffu}));
  EXPECT_FALSE(decodeHealth(std::vector<uint32_t>(17, 0xffffffffu)));
  EXPECT_FALSE(decodeMount(std::vector<uint32_t>(7)));  // one word too many
}

}  // namespace polyloc::t_protocol_frame
