// polylocd restarting under its clients: the generation goes up, old attachments turn stale
// and stay readable, re-attaching works, readers and writers follow the new segment.
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace polyloc::t_shm_restart {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using shm::Reader;
using shm::Segment;
using shm::Writer;

void publishPose(Writer& w, double x) {
  polyloc_pose p{};
  p.x = x;
  p.qw = 1;
  w.write(&p, sizeof p, static_cast<int64_t>(x * 1000));
}

double poseX(const std::vector<uint8_t>& p) { return reinterpret_cast<const polyloc_pose*>(p.data())->x; }

TEST(ShmRestart, ClientsSeeTheRestartAndReattach) {
  test::ShmName name;
  auto daemon = std::make_unique<Segment>(Segment::create(name, test::rigChannels()));
  daemon->ready();
  const uint32_t g1 = daemon->generation();
  EXPECT_GE(g1, 1u);

  auto client = Segment::attach(name);
  EXPECT_EQ(client.generation(), g1);
  EXPECT_FALSE(client.stale());
  Reader pose(client, client.find("pose"));
  Writer odom(client, client.find("odom"));
  {
    Writer out(*daemon, daemon->find("pose"));
    publishPose(out, 1.0);
  }
  std::vector<uint8_t> p;
  ASSERT_TRUE(pose.next(p));
  EXPECT_EQ(poseX(p), 1.0);

  // The restart: a new segment under the same name, generation + 1.
  daemon->stop();
  daemon.reset();
  EXPECT_TRUE(client.stale());
  auto restarted = Segment::create(name, test::rigChannels());
  restarted.ready();
  EXPECT_EQ(restarted.generation(), g1 + 1);
  EXPECT_TRUE(client.stale());
  // The old mapping is still there and readable (its last frames), nothing new in it.
  auto f = pose.newest(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(poseX(p), 1.0);
  EXPECT_FALSE(pose.wait(5'000'000));

  Writer out2(restarted, restarted.find("pose"));
  publishPose(out2, 2.0);
  client = Segment::attach(name);   // re-attach in place: readers and writers follow
  EXPECT_EQ(client.generation(), g1 + 1);
  EXPECT_FALSE(client.stale());
  ASSERT_TRUE(pose.wait(0));   // the new generation's frames are all new to the reader
  f = pose.next(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->frame, 0u);
  EXPECT_EQ(poseX(p), 2.0);
  polyloc_odometry o{};
  o.qw = 1;
  odom.write(&o, sizeof o, 1);   // claims the role in the new segment
  EXPECT_EQ(restarted.ring(restarted.find("odom"))->writer_pid, getpid());
  EXPECT_EQ(restarted.ring(restarted.find("odom"))->write_count, 1u);
}

TEST(ShmRestart, ReplacedWithoutStopIsStaleByGeneration) {
  test::ShmName name;
  auto first = Segment::create(name, test::rigChannels());
  first.ready();
  auto client = Segment::attach(name);
  EXPECT_FALSE(client.stale());
  auto second = Segment::create(name, test::rigChannels());   // e.g. after a crash
  EXPECT_EQ(second.generation(), first.generation() + 1);
  EXPECT_TRUE(client.stale());
  EXPECT_TRUE(first.stale());   // create() marked the replaced one STOPPED
  EXPECT_EQ(first.header().state, uint32_t{POLYLOC_STATE_STOPPED});
}

TEST(ShmRestart, DeadOwnerMakesItStaleAndTheNameReusable) {
  test::ShmName name;
  int pipefd[2];
  ASSERT_EQ(pipe(pipefd), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {   // a daemon that creates the segment and then hangs
    try {
      auto seg = Segment::create(name, test::rigChannels());
      seg.ready();
      char c = 1;
      if (write(pipefd[1], &c, 1) != 1) _exit(4);
      pause();
    } catch (...) {
    }
    _exit(3);
  }
  char c = 0;
  ASSERT_EQ(read(pipefd[0], &c, 1), 1);
  close(pipefd[0]);
  close(pipefd[1]);
  auto client = Segment::attach(name);
  EXPECT_EQ(client.header().owner_pid, child);
  EXPECT_FALSE(client.stale());
  // A second daemon on the same instance while the first runs: refused, naming it.
  try {
    Segment::create(name, test::rigChannels());
    ADD_FAILURE() << "replaced a live daemon's segment";
  } catch (const shm::ShmError& e) {
    EXPECT_EQ(e.code(), shm::ShmError::Errc::Busy);
    EXPECT_NE(std::string(e.what()).find(std::to_string(child)), std::string::npos) << e.what();
  }
  kill(child, SIGKILL);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(client.stale());   // state still READY, but its owner is gone
  auto next = Segment::create(name, test::rigChannels());
  EXPECT_EQ(next.generation(), client.generation() + 1);
}

TEST(ShmRestart, AttachBeforeReadyAndAfterUnlink) {
  test::ShmName name;
  try {
    Segment::attach(name);
    ADD_FAILURE();
  } catch (const shm::ShmError& e) {
    EXPECT_EQ(e.code(), shm::ShmError::Errc::NotFound);
    EXPECT_NE(std::string(e.what()).find("/polyloc." + name.str() + " does not exist"), std::string::npos) << e.what();
  }
  auto seg = Segment::create(name, test::rigChannels());
  try {
    Segment::attach(name);
    ADD_FAILURE();
  } catch (const shm::ShmError& e) {
    EXPECT_EQ(e.code(), shm::ShmError::Errc::NotReady);
  }
  seg.ready();
  auto client = Segment::attach(name);
  Segment::unlink(name);
  EXPECT_TRUE(client.stale());   // the name is gone
  EXPECT_THROW(client.ready(), std::logic_error);
}

}  // namespace
}  // namespace polyloc
