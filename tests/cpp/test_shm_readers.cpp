// Several readers at their own speed on one channel: a fast one, a slow one and one that falls
// behind; each frame any of them accepts is intact, and what they miss they count as overrun.
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace polyloc::t_shm_readers {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using namespace std::chrono_literals;
using shm::Reader;
using shm::Writer;

constexpr uint32_t kBytes = 4096;

struct Tally {
  uint64_t seen = 0, bad = 0, out_of_order = 0;
  int64_t last = -1;
  void take(const shm::FrameInfo& f, const uint8_t* p, size_t bytes) {
    ++seen;
    bad += !(bytes == kBytes && test::checkPattern(p, bytes, f.frame));
    out_of_order += static_cast<int64_t>(f.frame) <= last;
    last = static_cast<int64_t>(f.frame);
  }
};

TEST(ShmReaders, ThreeReadersAtDifferentSpeeds) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::blobChannel(POLYLOC_DIR_OUTPUT, 16, kBytes));
  seg.ready();
  constexpr uint64_t kFrames = 4000;
  std::atomic<bool> done{false};

  auto reader = [&](auto pause, Tally& t, Reader& r) {
    std::vector<uint8_t> p;
    for (;;) {
      if (auto f = r.next(p)) {
        t.take(*f, p.data(), p.size());
        pause(*f);
        continue;
      }
      if (done && !r.available()) break;
      r.wait(10'000'000);
    }
  };
  auto c1 = shm::Segment::attach(name), c2 = shm::Segment::attach(name), c3 = shm::Segment::attach(name);
  Reader fast(c1, 0), slow(c2, 0), behind(c3, 0);
  Tally tf, ts, tb;
  uint64_t behind_skip_from = 0, behind_after_skip = 0, behind_overruns_before = 0, behind_overruns_after = 0;
  std::thread t1([&] { reader([](const shm::FrameInfo&) {}, tf, fast); });
  std::thread t2([&] { reader([](const shm::FrameInfo&) { std::this_thread::sleep_for(200us); }, ts, slow); });
  std::thread t3([&] {
    bool slept = false;
    reader(
        [&](const shm::FrameInfo& f) {
          if (slept || f.frame < 500) return;
          slept = true;
          behind_overruns_before = behind.overruns();
          // Asleep while the writer laps the ring (16 slots) more than twice.
          while (__atomic_load_n(&seg.ring(0)->write_count, __ATOMIC_ACQUIRE) < f.frame + 40)
            std::this_thread::sleep_for(1ms);
          behind_skip_from = __atomic_load_n(&seg.ring(0)->write_count, __ATOMIC_ACQUIRE);
          std::vector<uint8_t> p;
          while (!behind.wait(10'000'000)) {
          }
          auto g = behind.next(p);
          ASSERT_TRUE(g);
          tb.take(*g, p.data(), p.size());
          behind_after_skip = g->frame;
          behind_overruns_after = behind.overruns();
        },
        tb, behind);
  });

  Writer w(seg, 0);
  for (uint64_t n = 0; n < kFrames; ++n) {
    test::fillPattern(w.begin(), kBytes, n);
    w.commit(kBytes, static_cast<int64_t>(n));
    std::this_thread::sleep_for(20us);
  }
  done = true;
  t1.join();
  t2.join();
  t3.join();

  for (auto* t : {&tf, &ts, &tb}) {
    EXPECT_EQ(t->bad, 0u);
    EXPECT_EQ(t->out_of_order, 0u);
    EXPECT_EQ(t->last, static_cast<int64_t>(kFrames - 1));   // everyone ends on the newest
  }
  // Every frame is either read or counted as lost.
  EXPECT_EQ(tf.seen + fast.overruns(), kFrames);
  EXPECT_EQ(ts.seen + slow.overruns(), kFrames);
  EXPECT_EQ(tb.seen + behind.overruns(), kFrames);
  std::printf("frames seen: fast %llu, slow %llu, behind %llu of %llu\n", static_cast<unsigned long long>(tf.seen),
              static_cast<unsigned long long>(ts.seen), static_cast<unsigned long long>(tb.seen),
              static_cast<unsigned long long>(kFrames));
  // The one that fell behind lost frames and went on at the newest, not at its old place.
  EXPECT_GT(behind_overruns_after, behind_overruns_before);
  EXPECT_GE(behind_after_skip + 1, behind_skip_from);
  EXPECT_GE(behind_after_skip, 500u + 39);
}

TEST(ShmReaders, NoTornFrameIsEverAcceptedFromAFullSpeedWriter) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::blobChannel(POLYLOC_DIR_OUTPUT, 2, kBytes));
  seg.ready();
  std::atomic<bool> done{false};
  std::thread writer([&] {
    Writer w(seg, 0);
    for (uint64_t n = 0; !done; ++n) {
      test::fillPattern(w.begin(), kBytes, n);
      w.commit(kBytes, 0);
    }
  });
  auto client = shm::Segment::attach(name);
  Reader copy(client, 0), in_place(client, 0);
  Tally tc, ti;
  std::vector<uint8_t> p;
  const auto end = std::chrono::steady_clock::now() + 300ms;
  while (std::chrono::steady_clock::now() < end) {
    if (auto f = copy.next(p)) tc.take(*f, p.data(), p.size());
    shm::FrameInfo info;
    bool intact = false;
    if (in_place.readInPlace([&](const shm::FrameInfo& f, const uint8_t* q) {
          info = f;
          intact = test::checkPattern(q, kBytes, f.frame);
        })) {
      ++ti.seen;
      ti.bad += !intact;
    }
  }
  done = true;
  writer.join();
  EXPECT_GT(tc.seen, 0u);
  EXPECT_GT(ti.seen, 0u);
  EXPECT_EQ(tc.bad, 0u);
  EXPECT_EQ(ti.bad, 0u);
  EXPECT_EQ(tc.out_of_order, 0u);
  std::printf("full-speed writer: copies %llu read, %llu torn retries; in place %llu read, %llu torn\n",
              static_cast<unsigned long long>(tc.seen), static_cast<unsigned long long>(copy.torn()),
              static_cast<unsigned long long>(ti.seen), static_cast<unsigned long long>(in_place.torn()));
}

}  // namespace
}  // namespace polyloc
