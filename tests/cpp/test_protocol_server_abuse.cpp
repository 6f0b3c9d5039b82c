// Clients that misbehave, over real loopback sockets: garbage, bad CRCs, frames never finished,
// replies never read, too many clients, and stop() with clients connected. Each gets an error
// reply where one can reach it and/or is closed; the server serves the others on.
#include "protocol_fixtures.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <sys/socket.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_protocol_server_abuse {

using namespace polyloc::protocol;
using polyloc::protocol::fake::eventually;
using polyloc::protocol::fake::TestServer;


Status frameError(Client& c) {
  const auto f = c.receive(2000);
  if (!f) return Status::Ok;
  EXPECT_EQ(f->command, cmd::FRAME_ERROR);
  return replyStatus(*f);
}

void expectPing(Client& c) {
  const Frame r = c.call(cmd::PING);
  EXPECT_EQ(r.command, replyId(cmd::PING));
  EXPECT_EQ(replyStatus(r), Status::Ok);
}


TEST(ProtocolServerAbuse, GarbageGetsAnErrorReplyThenTheStreamResynchronises) {
  TestServer t;
  auto c = t.connect();
  c->sendBytes(std::vector<uint8_t>{'G', 'E', 'T', ' ', '/', '\r', '\n'});
  EXPECT_EQ(frameError(*c), Status::BadMagic);
  expectPing(*c);  // same connection, next good frame
  auto bad = encodeFrame(cmd::GETPOSE);
  bad.back() ^= 0x55;
  c->sendBytes(bad);
  const auto f = c->receive(2000);
  ASSERT_TRUE(f);
  EXPECT_EQ(replyStatus(*f), Status::BadCrc);
  EXPECT_EQ(f->data.at(1), cmd::GETPOSE);  // detail: the command as read
  expectPing(*c);
  const auto n = t.server.counters();
  EXPECT_EQ(n.bad_magic, 1u);
  EXPECT_EQ(n.bad_crc, 1u);
}

TEST(ProtocolServerAbuse, TooManyFrameErrorsCloseTheConnectionNotTheServer) {
  ServerConfig cfg;
  cfg.max_frame_errors = 3;
  cfg.max_frame_bytes = 1024;
  TestServer t(cfg);
  auto c = t.connect();
  auto big = encodeFrame(cmd::PING, std::vector<uint32_t>(300));  // 1216 bytes > 1024
  c->sendBytes(big);
  EXPECT_EQ(frameError(*c), Status::FrameTooLarge);
  expectPing(*c);  // found after the skipped frame
  auto size = encodeFrame(cmd::PING);
  storeLE32(size.data() + 4, 13);
  c->sendBytes(size);
  EXPECT_EQ(frameError(*c), Status::BadFrameSize);
  expectPing(*c);
  c->sendBytes(std::vector<uint8_t>(100, 0xee));  // garbage
  c->sendBytes(encodeFrame(cmd::PING));
  EXPECT_EQ(frameError(*c), Status::BadMagic);
  EXPECT_TRUE(c->waitClosed(3000));  // third error: closed, the PING after it unanswered
  auto second = t.connect();
  expectPing(*second);
  ASSERT_TRUE(eventually([&] { return t.server.counters().closed_frame_errors == 1; }));
  const auto n = t.server.counters();
  EXPECT_EQ(n.frame_too_large, 1u);
  EXPECT_EQ(n.bad_frame_size, 1u);
  EXPECT_EQ(n.open, 1u);
}

TEST(ProtocolServerAbuse, PartialFrameIsClosedAfterTheTimeout) {
  ServerConfig cfg;
  cfg.frame_timeout_ms = 200;
  TestServer t(cfg);
  auto c = t.connect();
  auto other = t.connect();
  const auto frame = encodeFrame(cmd::GETPOSE);
  const auto start = std::chrono::steady_clock::now();
  c->sendBytes(std::span(frame).first(10));
  expectPing(*other);  // the half frame holds nobody up
  EXPECT_EQ(frameError(*c), Status::FrameTimeout);
  EXPECT_TRUE(c->waitClosed(2000));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(s, 0.19);
  EXPECT_LT(s, 1.5);
  ASSERT_TRUE(eventually([&] { return t.server.counters().closed_frame_timeout == 1; }));
  EXPECT_EQ(t.server.counters().frame_timeouts, 1u);
  expectPing(*other);
}

TEST(ProtocolServerAbuse, ATrickleThatNeverCompletesIsClosedToo) {
  ServerConfig cfg;
  cfg.frame_timeout_ms = 300;
  TestServer t(cfg);
  auto c = t.connect();
  const auto frame = encodeFrame(cmd::PING, std::vector<uint32_t>(64));
  bool closed = false;
  for (size_t i = 0; i < frame.size() && !closed; ++i) {  // one byte per 50 ms: 13 s for the frame
    try {
      c->sendBytes(std::span(frame).subspan(i, 1));
    } catch (const std::runtime_error&) {
      closed = true;  // reset: the server closed it
    }
    closed = closed || (c->receive(50) && c->waitClosed(1000));
  }
  EXPECT_TRUE(closed);
  EXPECT_TRUE(eventually([&] { return t.server.counters().closed_frame_timeout == 1; }));
}

TEST(ProtocolServerAbuse, IdleClientIsClosed) {
  ServerConfig cfg;
  cfg.idle_timeout_ms = 150;
  TestServer t(cfg);
  auto c = t.connect();
  expectPing(*c);
  EXPECT_TRUE(c->waitClosed(2000));
  EXPECT_TRUE(eventually([&] { return t.server.counters().closed_idle == 1; }));
}

TEST(ProtocolServerAbuse, SilentClientsAreClosedAndFreeTheirPlaces) {
  // Clients that connect and never send a frame would hold every place until the idle timeout.
  ServerConfig cfg;
  cfg.max_clients = 2;
  cfg.first_frame_timeout_ms = 200;
  TestServer t(cfg);
  auto a = t.connect(), b = t.connect();
  EXPECT_EQ(frameError(*a), Status::FrameTimeout);
  EXPECT_EQ(frameError(*b), Status::FrameTimeout);
  ASSERT_TRUE(eventually([&] { return t.server.counters().open == 0; }));
  EXPECT_EQ(t.server.counters().closed_frame_timeout, 2u);
  auto c = t.connect();
  expectPing(*c);  // a client that speaks is served, and kept past the first-frame timeout
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  expectPing(*c);
}

TEST(ProtocolServerAbuse, SlowClientIsClosedWhileOthersAreServed) {
  ServerConfig cfg;
  cfg.max_queued_bytes = 256 * 1024;
  TestServer t(cfg);
  t.handler.lock(), t.handler.scan_beams = 8000;  // 64 KB a reply
  auto slow = t.connect();
  const int small = 4096;
  setsockopt(slow->fd(), SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  auto reader = t.connect();
  // 1000 scan requests (about 64 MB of replies) that it never reads.
  std::vector<uint8_t> requests;
  for (int i = 0; i < 1000; ++i) appendFrame(requests, cmd::GETSCANRADIALSCANNER, std::vector<uint32_t>{1});
  slow->sendBytes(requests);
  ASSERT_TRUE(eventually([&] { return t.server.counters().closed_slow == 1; }, 10000));
  expectPing(*reader);
  const Frame r = reader->call(cmd::GETSCANRADIALSCANNER, std::vector<uint32_t>{1});
  EXPECT_EQ(replyStatus(r), Status::Ok);
  EXPECT_EQ(t.server.counters().open, 1u);
}

TEST(ProtocolServerAbuse, TooManyClientsGetBusy) {
  ServerConfig cfg;
  cfg.max_clients = 2;
  TestServer t(cfg);
  auto a = t.connect(), b = t.connect();
  expectPing(*a), expectPing(*b);
  auto c = t.connect();
  EXPECT_EQ(frameError(*c), Status::Busy);
  EXPECT_TRUE(c->waitClosed(2000));
  a.reset();  // one leaves: room for another
  ASSERT_TRUE(eventually([&] { return t.server.counters().open == 1; }));
  auto d = t.connect();
  expectPing(*d);
  EXPECT_EQ(t.server.counters().closed_busy, 1u);
}

TEST(ProtocolServerAbuse, ManyClientsAtOnce) {
  TestServer t;
  std::atomic<int> good{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < 12; ++k)
    threads.emplace_back([&, k] {
      auto c = t.connect();
      for (int i = 0; i < 50; ++i) {
        const Frame r = c->call(cmd::PING, std::vector<uint32_t>{uint32_t(k), uint32_t(i)});
        if (r.data == std::vector<uint32_t>{0, uint32_t(k), uint32_t(i)}) ++good;
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(good, 600);
  EXPECT_EQ(t.server.counters().frames, 600u);
  ASSERT_TRUE(eventually([&] { return t.server.counters().closed_peer == 12; }));
}

TEST(ProtocolServerAbuse, RepliesStillComeAfterTheClientShutsItsSide) {
  TestServer t;
  auto c = t.connect();
  std::vector<uint8_t> requests;
  for (int i = 0; i < 3; ++i) appendFrame(requests, cmd::GETNUMSCANNERS, {});
  c->sendBytes(requests);
  ::shutdown(c->fd(), SHUT_WR);  // as `printf ... | nc` does
  for (int i = 0; i < 3; ++i) {
    const auto f = c->receive(2000);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->data, (std::vector<uint32_t>{0, 3}));
  }
  EXPECT_TRUE(c->waitClosed(2000));
}

TEST(ProtocolServerAbuse, StopWithClientsConnected) {
  fake::FakeHandler h;
  Server s({}, h);
  s.start();
  auto a = std::make_unique<Client>("127.0.0.1", s.port());
  auto b = std::make_unique<Client>("127.0.0.1", s.port());
  expectPing(*a);
  const auto ping = encodeFrame(cmd::PING);
  b->sendBytes(std::span(ping).first(5));  // mid-frame
  ASSERT_TRUE(eventually([&] { return s.counters().bytes_in >= 21; }));
  const auto start = std::chrono::steady_clock::now();
  std::thread([&] { s.stop(); }).join();  // from another thread
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_FALSE(s.running());
  EXPECT_EQ(s.counters().closed_stopped, 2u);
  EXPECT_EQ(s.counters().open, 0u);
  EXPECT_TRUE(a->waitClosed(1000));
  EXPECT_TRUE(b->waitClosed(1000));
  s.stop();   // idempotent
  s.start();  // and it starts again
  Client c("127.0.0.1", s.port());
  expectPing(c);
}

}  // namespace polyloc::t_protocol_server_abuse
