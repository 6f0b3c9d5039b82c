// One channel, one writer, readers in one process: round trip, start positions, overrun,
// in-place reads, wake-ups, the doorbell and the writer role.
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <tuple>
#include <thread>

namespace polyloc::t_shm_channel {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using shm::Reader;
using shm::Writer;

shm::Segment odomSegment(const std::string& name, uint32_t slots) {
  return shm::Segment::create(name, {test::spec("odom", POLYLOC_KIND_ODOMETRY, POLYLOC_DIR_INPUT, slots)});
}

// An odometry channel of `slots` slots with a writer and a reader from the next frame.
struct OdomRing {
  explicit OdomRing(uint32_t slots) : seg(odomSegment(name, slots)), w(seg, 0), r(seg, 0) {}
  test::ShmName name;
  shm::Segment seg;
  Writer w;
  Reader r;
  polyloc_odometry o{};
};

TEST(ShmChannel, WriteReadRoundTrip) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::rigChannels());
  seg.ready();
  auto client = shm::Segment::attach(name);   // a second mapping, as a client has
  const int ch = client.find("scan/front");
  ASSERT_EQ(ch, 0);
  Reader r(client, ch);
  Writer w(client, ch);
  std::vector<uint8_t> payload;
  EXPECT_FALSE(r.next(payload));
  EXPECT_FALSE(r.newest(payload));

  std::vector<uint8_t> frame(2180);
  for (uint64_t n = 0; n < 3; ++n) {
    test::fillPattern(frame.data(), frame.size(), n);
    w.write(frame.data(), static_cast<uint32_t>(frame.size()), 1000 + static_cast<int64_t>(n));
  }
  EXPECT_EQ(w.written(), 3u);
  EXPECT_EQ(r.available(), 3u);
  for (uint64_t n = 0; n < 3; ++n) {
    auto f = r.next(payload);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->frame, n);
    EXPECT_EQ(f->size, 2180u);
    EXPECT_EQ(f->kind, uint32_t{POLYLOC_KIND_RANGES});
    EXPECT_EQ(f->stamp_ns, 1000 + static_cast<int64_t>(n));
    EXPECT_GT(f->publish_ns, 0);
    ASSERT_EQ(payload.size(), 2180u);
    EXPECT_TRUE(test::checkPattern(payload.data(), payload.size(), n));
  }
  EXPECT_FALSE(r.next(payload));
  EXPECT_EQ(r.overruns(), 0u);
  // newest() gives the last frame again, even when read already.
  auto f = r.newest(payload);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->frame, 2u);
  // The owner's mapping sees the same frames.
  Reader owner_side(seg, seg.find("scan/front"), Reader::Start::Oldest);
  EXPECT_EQ(owner_side.available(), 3u);
}

TEST(ShmChannel, StartPositions) {
  test::ShmName name;
  auto seg = odomSegment(name, 4);
  Writer w(seg, 0);
  polyloc_odometry o{};
  for (int i = 0; i < 6; ++i) w.write(&o, sizeof o, i);
  std::vector<uint8_t> p;
  Reader next(seg, 0, Reader::Start::Next), newest(seg, 0, Reader::Start::Newest), oldest(seg, 0, Reader::Start::Oldest);
  EXPECT_FALSE(next.next(p));
  EXPECT_EQ(newest.next(p)->frame, 5u);
  EXPECT_EQ(oldest.next(p)->frame, 2u);   // 4 slots: frames 2..5 are still there
  EXPECT_EQ(oldest.overruns(), 0u);
}

TEST(ShmChannel, OverrunSkipsToNewestAndCounts) {
  OdomRing ring(4);
  auto [w, r, o] = std::tie(ring.w, ring.r, ring.o);
  for (int i = 0; i < 10; ++i) w.write(&o, sizeof o, i);
  EXPECT_EQ(r.available(), 4u);
  std::vector<uint8_t> p;
  auto f = r.next(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->frame, 9u);
  EXPECT_EQ(r.overruns(), 9u);
  EXPECT_FALSE(r.next(p));
}

TEST(ShmChannel, ReadInPlaceSeesTheSlotAndDetectsAnOverwrite) {
  OdomRing ring(1);
  auto [w, r, o] = std::tie(ring.w, ring.r, ring.o);
  o.x = 1.5;
  w.write(&o, sizeof o, 1);
  double x = 0;
  EXPECT_TRUE(r.readInPlace([&](const shm::FrameInfo& f, const uint8_t* p) {
    EXPECT_EQ(f.size, sizeof o);
    x = reinterpret_cast<const polyloc_odometry*>(p)->x;
  }));
  EXPECT_EQ(x, 1.5);
  EXPECT_FALSE(r.readInPlace([](const shm::FrameInfo&, const uint8_t*) { ADD_FAILURE() << "no new frame"; }));
  // One slot: a write during the read overwrites the frame being read.
  w.write(&o, sizeof o, 2);
  EXPECT_FALSE(r.readInPlace([&](const shm::FrameInfo&, const uint8_t*) { w.write(&o, sizeof o, 3); }));
  EXPECT_EQ(r.torn(), 1u);
  std::vector<uint8_t> p;
  auto f = r.next(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->frame, 2u);   // frame 1 was lost, frame 2 (stamp 3) is read next
  EXPECT_EQ(f->stamp_ns, 3);
}

TEST(ShmChannel, WaitTimesOutAndWakesOnPublish) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::rigChannels());
  const int ch = seg.find("pose");
  Reader r(seg, ch);
  EXPECT_FALSE(r.wait(0));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(r.wait(20'000'000));
  EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(19));

  Writer w(seg, ch);
  std::thread t([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    polyloc_pose p{};
    w.write(&p, sizeof p, 7);
  });
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_TRUE(r.wait(5'000'000'000));
  EXPECT_LT(std::chrono::steady_clock::now() - t1, std::chrono::seconds(4));
  t.join();
  EXPECT_TRUE(r.wait(0));   // still unread
  std::vector<uint8_t> p;
  EXPECT_TRUE(r.next(p));
  EXPECT_FALSE(r.wait(0));
  // Spinning first changes nothing about the result.
  EXPECT_FALSE(r.wait(1'000'000, 500'000));
}

TEST(ShmChannel, InputsRingTheDoorbellOutputsDoNot) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::rigChannels());
  seg.ready();
  const uint32_t seen = shm::doorbell(seg);
  EXPECT_FALSE(shm::waitDoorbell(seg, seen, 0));
  Writer pose(seg, seg.find("pose"));
  polyloc_pose p{};
  pose.write(&p, sizeof p, 1);
  EXPECT_EQ(shm::doorbell(seg), seen);
  auto client = shm::Segment::attach(name);
  Writer odom(client, client.find("odom"));
  std::thread t([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    polyloc_odometry o{};
    odom.write(&o, sizeof o, 1);
  });
  EXPECT_TRUE(shm::waitDoorbell(seg, seen, 5'000'000'000));
  t.join();
  EXPECT_EQ(shm::doorbell(seg), seen + 1);
  EXPECT_TRUE(shm::waitDoorbell(seg, seen, 0));
}

TEST(ShmChannel, WriterRoleIsClaimedReleasedAndSizesChecked) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::rigChannels());
  const int ch = seg.find("odom");
  {
    Writer w(seg, ch);
    EXPECT_EQ(seg.ring(ch)->writer_pid, getpid());
    EXPECT_EQ(seg.ring(ch)->writer_claims, 1u);
    Writer again(seg, ch);   // the same process may write again (e.g. after re-creating it)
    std::vector<uint8_t> big(seg.channel(ch).payload_max + 1);
    EXPECT_THROW(w.write(big.data(), static_cast<uint32_t>(big.size()), 1), std::length_error);
    EXPECT_EQ(seg.slot(ch, 0)->seq, 0u);   // a refused frame leaves no odd seq
    EXPECT_THROW(w.commit(8, 1), std::logic_error);
  }
  EXPECT_EQ(seg.ring(ch)->writer_pid, 0);
  // A live holder that is another process: busy unless taken over.
  seg.ring(ch)->writer_pid = getppid();
  try {
    Writer w(seg, ch);
    ADD_FAILURE() << "claimed a channel held by a live process";
  } catch (const shm::ShmError& e) {
    EXPECT_EQ(e.code(), shm::ShmError::Errc::Busy);
    EXPECT_NE(std::string(e.what()).find("channel 'odom' of /polyloc." + name.str()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::to_string(getppid())), std::string::npos) << e.what();
  }
  Writer forced(seg, ch, true);
  EXPECT_EQ(seg.ring(ch)->writer_pid, getpid());
  // Taken over by another process meanwhile: the old writer's next frame is refused.
  seg.ring(ch)->writer_pid = getppid();
  EXPECT_THROW(forced.begin(), shm::ShmError);
  seg.ring(ch)->writer_pid = getpid();
}

}  // namespace
}  // namespace polyloc
