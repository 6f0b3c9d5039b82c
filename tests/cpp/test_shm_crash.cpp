// A writer process that dies mid-frame: its frame never becomes visible, it leaves no lock,
// and the next writer takes the role over and continues the channel.
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

namespace polyloc::t_shm_crash {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using shm::Reader;
using shm::Writer;

constexpr uint32_t kBytes = 2048;

// Reaps the child so that kill(pid, 0) says ESRCH afterwards (a zombie still counts as alive).
void killAndReap(pid_t pid) {
  kill(pid, SIGKILL);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status));
}

TEST(ShmCrash, WriterStoppedAndKilledMidFrameLeavesNothingVisible) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::blobChannel(POLYLOC_DIR_INPUT, 4, kBytes));
  seg.ready();

  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {   // the client: 10 frames, then half of frame 10, then it stops
    try {
      auto c = shm::Segment::attach(name);
      Writer w(c, 0);
      for (uint64_t n = 0; n < 10; ++n) {
        test::fillPattern(w.begin(), kBytes, n);
        w.commit(kBytes, static_cast<int64_t>(n));
      }
      uint8_t* p = w.begin();
      std::vector<uint8_t> frame(kBytes);
      test::fillPattern(frame.data(), kBytes, 10);
      std::memcpy(p, frame.data(), kBytes / 2);
      raise(SIGSTOP);
    } catch (...) {
    }
    _exit(3);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, WUNTRACED), child);
  ASSERT_TRUE(WIFSTOPPED(status));

  // Mid-frame: seq odd, write_count 10. Of the 4 slots, frame 6's holds half of frame 10 now:
  // a reader from the oldest gets 7..9 and counts 6 as lost, and never sees frame 10.
  EXPECT_EQ(seg.ring(0)->write_count, 10u);
  EXPECT_EQ(seg.slot(0, 10)->seq, 2u * 10 + 1);
  Reader r(seg, 0, Reader::Start::Oldest);
  std::vector<uint8_t> p;
  uint64_t expect = 7;
  while (auto f = r.next(p)) {
    EXPECT_EQ(f->frame, expect++);
    EXPECT_TRUE(test::checkPattern(p.data(), p.size(), f->frame));
  }
  EXPECT_EQ(expect, 10u);
  EXPECT_FALSE(r.wait(20'000'000));
  // While the stopped writer lives, the role is its own.
  EXPECT_THROW(Writer(seg, 0), shm::ShmError);

  killAndReap(child);
  EXPECT_EQ(seg.ring(0)->writer_pid, child);   // left behind, but no lock: a dead holder is replaced
  Writer next(seg, 0);
  EXPECT_EQ(seg.ring(0)->writer_pid, getpid());
  EXPECT_EQ(seg.ring(0)->writer_claims, 2u);
  for (uint64_t n = 10; n < 13; ++n) {
    test::fillPattern(next.begin(), kBytes, n);
    next.commit(kBytes, static_cast<int64_t>(n));
  }
  // Frame 10 is the new writer's, whole; then 11 and 12.
  while (auto f = r.next(p)) {
    EXPECT_EQ(f->frame, expect++);
    EXPECT_TRUE(test::checkPattern(p.data(), p.size(), f->frame)) << "frame " << f->frame;
  }
  EXPECT_EQ(expect, 13u);
  EXPECT_EQ(r.overruns(), 1u);
}

TEST(ShmCrash, WriterKilledAtRandomMomentsNeverShowsATornFrame) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::blobChannel(POLYLOC_DIR_INPUT, 2, kBytes));
  seg.ready();
  auto client = shm::Segment::attach(name);
  Reader r(client, 0);
  std::vector<uint8_t> p;
  uint64_t seen = 0, bad = 0;
  int64_t last = -1;
  const auto drain = [&] {
    while (auto f = r.next(p)) {
      ++seen;
      bad += !test::checkPattern(p.data(), p.size(), f->frame) || p.size() != kBytes;
      EXPECT_GT(static_cast<int64_t>(f->frame), last);
      last = static_cast<int64_t>(f->frame);
    }
  };
  for (int round = 0; round < 6; ++round) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {   // writes as fast as it can until killed; takes the role of the last one
      try {
        auto c = shm::Segment::attach(name);
        Writer w(c, 0);
        for (;;) {
          const uint64_t n = w.written();
          test::fillPattern(w.begin(), kBytes, n);
          w.commit(kBytes, 0);
        }
      } catch (...) {
      }
      _exit(3);
    }
    // Once it writes, read while it does, then kill it at some moment, likely inside a frame.
    const uint64_t before = seg.ring(0)->write_count;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (__atomic_load_n(&seg.ring(0)->write_count, __ATOMIC_ACQUIRE) < before + 10 &&
           std::chrono::steady_clock::now() < give_up)
      drain();
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(5 + 7 * round);
    while (std::chrono::steady_clock::now() < end) drain();
    killAndReap(child);
    drain();
  }
  EXPECT_GT(seen, 0u);
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(seg.ring(0)->writer_claims, 6u);   // each child after the first took over a dead holder
}

}  // namespace
}  // namespace polyloc
