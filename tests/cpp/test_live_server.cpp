// The live view's server against a hostile client (docs/live.md, "What one client can make the
// server hold"). The client is a few lines of WebSocket over a plain socket, so that it can do
// what a well-behaved library would not: never read, flood, hold a connection in its handshake.
#include "live/foxglove_server.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_live_server {


using namespace polyloc::live;
using json = nlohmann::json;
using Bytes = std::vector<uint8_t>;
using Clock = std::chrono::steady_clock;

ChannelSpec channel(const std::string& topic, bool latched) { return {topic, "json", "x", "{}", "jsonschema", latched}; }

bool dialInto(int fd, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET, a.sin_port = htons(port);
  inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
  return connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
}

struct Frame {
  int opcode = -1;  // -1: nothing within the time; 8: closed (a close frame or EOF)
  std::string payload;
};

class RawClient {
 public:
  explicit RawClient(uint16_t port) : fd_(socket(AF_INET, SOCK_STREAM, 0)) { connected_ = dialInto(fd_, port); }
  ~RawClient() { close(fd_); }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  // The opening handshake with the Foxglove subprotocol, then serverInfo and advertise.
  bool open() {
    if (!connected_) return false;
    const std::string req =
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
        "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n";
    if (!write(req)) return false;
    size_t end;
    while ((end = buf_.find("\r\n\r\n")) == std::string::npos)
      if (!fill(5000)) return false;
    const bool upgraded = buf_.rfind("HTTP/1.1 101", 0) == 0;
    buf_.erase(0, end + 4);
    return upgraded && next().opcode == 1 && next().opcode == 1;
  }

  // A masked text frame (mask key 0: the payload goes as it is).
  bool sendText(const std::string& text) {
    std::string f(1, char(0x81));
    if (text.size() < 126) {
      f += char(0x80 | text.size());
    } else {
      f += char(0x80 | 126);
      f += char(text.size() >> 8), f += char(text.size() & 0xff);
    }
    f += std::string(4, '\0') + text;
    return write(f);
  }

  // The next frame from the server within `ms`.
  Frame next(int ms = 5000) {
    for (;;) {
      if (buf_.size() >= 2) {
        const auto b = [&](size_t i) { return uint64_t(uint8_t(buf_[i])); };
        uint64_t len = b(1) & 0x7f;
        size_t head = 2;
        if (len == 126) head = 4, len = buf_.size() >= 4 ? (b(2) << 8 | b(3)) : ~0ull;
        if (len == 127) {
          head = 10, len = 0;
          for (size_t i = 2; i < 10 && buf_.size() >= 10; ++i) len = len << 8 | b(i);
          if (buf_.size() < 10) len = ~0ull;
        }
        if (len != ~0ull && buf_.size() >= head + len) {
          Frame f{int(b(0) & 0x0f), buf_.substr(head, len)};
          buf_.erase(0, head + len);
          return f;
        }
      }
      if (closed_) return {8, {}};
      if (!fill(ms)) return closed_ ? Frame{8, {}} : Frame{};
    }
  }

  // Every frame that comes within `ms` of quiet.
  std::vector<Frame> drain(int ms) {
    std::vector<Frame> all;
    for (Frame f = next(ms); f.opcode != -1; f = next(ms)) {
      all.push_back(f);
      if (f.opcode == 8) break;
    }
    return all;
  }

  // Whether the server closed the connection within `ms` (what it sent before is skipped).
  bool closedWithin(int ms) {
    const auto until = Clock::now() + std::chrono::milliseconds(ms);
    while (!closed_ && Clock::now() < until) {
      fill(50);
      buf_.clear();
    }
    return closed_;
  }

  int fd() const { return fd_; }

 private:
  bool write(const std::string& s) {
    for (size_t done = 0; done < s.size();) {
      const ssize_t n = ::send(fd_, s.data() + done, s.size() - done, MSG_NOSIGNAL);  // no SIGPIPE once closed
      if (n <= 0) return false;
      done += size_t(n);
    }
    return true;
  }
  bool fill(int ms) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, ms) <= 0) return false;
    char tmp[1 << 16];
    const ssize_t n = read(fd_, tmp, sizeof tmp);
    if (n <= 0) {
      closed_ = true;
      return false;
    }
    buf_.append(tmp, size_t(n));
    return true;
  }

  int fd_;
  bool connected_ = false, closed_ = false;
  std::string buf_;
};

json subscribeAll(uint64_t first_id, size_t n, uint64_t channel_id) {
  json list = json::array();
  for (size_t i = 0; i < n; ++i) list.push_back({{"id", first_id + i}, {"channelId", channel_id}});
  return json{{"op", "subscribe"}, {"subscriptions", list}};
}

template <class Pred> bool eventually(Pred p, int ms = 5000) {
  const auto until = Clock::now() + std::chrono::milliseconds(ms);
  while (!p()) {
    if (Clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

ServerConfig anyPort() {
  ServerConfig c;
  c.port = 0;
  return c;
}

// The protocol has no authentication: a view opened beyond this computer says so at start, one
// on the loopback does not (was: live.address 0.0.0.0 accepted silently).
TEST(FoxgloveServerLimits, AViewOpenToOtherHostsWarnsAtStart) {
  auto ring = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(16);
  const auto before = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("live_test", ring));
  auto warned = [&] {
    for (const std::string& line : ring->last_formatted())
      if (line.find("open to every host that reaches it (no authentication)") != std::string::npos) return true;
    return false;
  };
  {
    FoxgloveServer local(anyPort());
    local.start();
  }
  EXPECT_FALSE(warned());
  ServerConfig open = anyPort();
  open.address = "0.0.0.0";
  {
    FoxgloveServer s(open);
    s.start();
  }
  EXPECT_TRUE(warned());
  spdlog::set_default_logger(before);
}

// Was: 800 ids on the latched /map queued the map 800 times (forced sends), RSS +483 MB.
TEST(FoxgloveServerLimits, TheLatchedMapGoesOncePerClientHoweverManyIdsNameIt) {
  FoxgloveServer s(anyPort());
  const uint32_t map = s.addChannel(channel("/map", true));
  s.start();
  s.publish(map, 5, Bytes(600'000, 7));
  RawClient c(s.port());
  ASSERT_TRUE(c.open());
  ASSERT_TRUE(c.sendText(subscribeAll(1, 800, map).dump()));
  int binaries = 0, errors = 0;
  for (const Frame& f : c.drain(1500)) {
    if (f.opcode == 2) {
      ++binaries;
      EXPECT_EQ(f.payload.size(), 13u + 600'000u);
    } else if (f.opcode == 1 && json::parse(f.payload).value("level", 0) == 2) {
      ++errors;
      EXPECT_NE(f.payload.find("at most 64 subscriptions"), std::string::npos) << f.payload;
    }
  }
  EXPECT_EQ(binaries, 1);
  EXPECT_EQ(errors, 1);  // one answer for the whole list, not one per id
  EXPECT_EQ(s.stats().messages_sent, 1u);
  EXPECT_TRUE(s.subscribed(map));
}

// Was: a latched send skipped max_queue (forced); now it waits for room and is not lost.
TEST(FoxgloveServerLimits, LatchedSendsKeepToTheQueueLimitAndComeWhenThereIsRoom) {
  ServerConfig cfg = anyPort();
  cfg.max_queue_bytes = 1'000'000;
  FoxgloveServer s(cfg);
  const uint32_t a = s.addChannel(channel("/a", true)), b = s.addChannel(channel("/b", true));
  const uint32_t pose = s.addChannel(channel("/pose", false));
  s.start();
  s.publish(a, 1, Bytes(700'000, 1));
  s.publish(b, 2, Bytes(700'000, 2));
  RawClient c(s.port());
  ASSERT_TRUE(c.open());
  json subs = subscribeAll(1, 1, a);
  subs["subscriptions"].push_back({{"id", 2}, {"channelId", b}});
  subs["subscriptions"].push_back({{"id", 3}, {"channelId", pose}});
  ASSERT_TRUE(c.sendText(subs.dump()));
  ASSERT_TRUE(eventually([&] { return s.stats().messages_dropped == 1; })) << s.stats().messages_dropped;
  EXPECT_EQ(s.stats().messages_sent, 1u);  // both in one go would be 1.4 MB over a 1 MB queue
  std::vector<Frame> got = c.drain(500);   // reading empties the queue
  ASSERT_EQ(got.size(), 1u);
  s.publish(pose, 3, Bytes{'{', '}'});     // the next message for the client pays what it is owed first
  for (const Frame& f : c.drain(1000)) got.push_back(f);
  ASSERT_EQ(got.size(), 3u);
  uint32_t subs_seen[3];
  for (int i = 0; i < 3; ++i) std::memcpy(&subs_seen[i], got[size_t(i)].payload.data() + 1, 4);
  EXPECT_EQ(subs_seen[0], 1u);
  EXPECT_EQ(subs_seen[1], 2u);
  EXPECT_EQ(got[1].payload.size(), 13u + 700'000u);
  EXPECT_EQ(subs_seen[2], 3u);
}

// Was: id 2^32 + 1 silently became subscription 1.
TEST(FoxgloveServerLimits, IdsBeyond32BitsAreRefusedNotWrapped) {
  FoxgloveServer s(anyPort());
  const uint32_t ch = s.addChannel(channel("/pose", false));
  s.start();
  RawClient c(s.port());
  ASSERT_TRUE(c.open());
  const uint64_t big = (uint64_t(1) << 32) + 1;
  for (const json& m : {subscribeAll(big, 1, ch), subscribeAll(1, 1, big),
                        json{{"op", "unsubscribe"}, {"subscriptionIds", {big}}}}) {
    ASSERT_TRUE(c.sendText(m.dump()));
    const Frame f = c.next();
    ASSERT_EQ(f.opcode, 1) << m;
    EXPECT_EQ(json::parse(f.payload).value("level", 0), 2) << f.payload;
    EXPECT_NE(f.payload.find("4294967295"), std::string::npos) << f.payload;
  }
  EXPECT_FALSE(s.subscribed(ch));
  EXPECT_EQ(s.stats().bad_messages, 3u);
}

// Was: a subscribe/unsubscribe storm was served in full (pose latency p50 42 -> 345 ms).
TEST(FoxgloveServerLimits, AMessageStormIsCutOffAndOtherViewersGoOn) {
  ServerConfig cfg = anyPort();
  cfg.max_client_rate = 50;
  FoxgloveServer s(cfg);
  const uint32_t ch = s.addChannel(channel("/pose", false));
  s.start();
  RawClient calm(s.port()), storm(s.port());
  ASSERT_TRUE(calm.open());
  ASSERT_TRUE(storm.open());
  ASSERT_TRUE(calm.sendText(subscribeAll(1, 1, ch).dump()));
  for (int i = 0; i < 400; ++i) {  // valid messages, far too many: the server stops reading them
    const json m = i % 2 ? json{{"op", "unsubscribe"}, {"subscriptionIds", {7}}} : subscribeAll(7, 1, ch);
    if (!storm.sendText(m.dump())) break;  // closed under us
  }
  EXPECT_TRUE(storm.closedWithin(5000));
  const ServerStats st = s.stats();
  EXPECT_GE(st.rate_limited, 20u);  // max_bad_messages of them close the client
  EXPECT_LE(st.rate_limited, 400u - 50u);
  ASSERT_TRUE(eventually([&] { return s.subscribed(ch); }));
  s.publish(ch, 9, Bytes{'{', '}'});
  EXPECT_EQ(calm.next().opcode, 2);
}

// Was: max_clients counted only finished handshakes; ~200 idle connections used up polylocd's
// file descriptors and locked out the control endpoint.
TEST(FoxgloveServerLimits, IdleConnectionsAreBoundedAndClosed) {
  ServerConfig cfg = anyPort();
  cfg.max_pending = 4, cfg.handshake_timeout_s = 0.5;
  FoxgloveServer s(cfg);
  s.addChannel(channel("/pose", false));
  s.start();
  std::vector<std::unique_ptr<RawClient>> idle;
  for (int i = 0; i < 40; ++i) idle.push_back(std::make_unique<RawClient>(s.port()));  // connect, say nothing
  int closed = 0;
  for (auto& c : idle) closed += c->closedWithin(3000);  // at once, or after the 0.5 s handshake timeout
  EXPECT_EQ(closed, 40);
  EXPECT_GE(s.stats().refused_pending, 20u);
  RawClient good(s.port());  // the limit counts connections in their handshake: a viewer gets in
  EXPECT_TRUE(good.open());
}

// Was: with no file descriptor left, websocketpp re-accepted at once in a loop (a core at 40 %).
TEST(FoxgloveServerLimits, AFailedAcceptPausesInsteadOfSpinning) {
  FoxgloveServer s(anyPort());
  s.addChannel(channel("/pose", false));
  s.start();
  std::vector<int> fds;
  for (int i = 0; i < 3; ++i) fds.push_back(socket(AF_INET, SOCK_STREAM, 0));
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &old), 0);
  int top = 0;
  for (int fd = 0; fd < 4096; ++fd)
    if (fcntl(fd, F_GETFD) != -1) top = fd;
  rlimit tight = old;
  tight.rlim_cur = rlim_t(top + 1);  // no new descriptor for anyone: the server's accept fails
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &tight), 0);
  std::vector<int> fillers;  // the holes below the limit (descriptors closed earlier) taken too
  for (int f; (f = dup(fds[0])) >= 0;) fillers.push_back(f);
  for (int fd : fds) dialInto(fd, s.port());  // the kernel completes them; accept cannot take them
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  const uint64_t errors = s.stats().accept_errors;
  for (int f : fillers) close(f);
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &old), 0);
  EXPECT_GE(errors, 1u);
  EXPECT_LE(errors, 10u);  // one try per 0.2 s, not a loop
  for (int fd : fds) close(fd);
  RawClient good(s.port());  // and accepting resumes once descriptors are free
  EXPECT_TRUE(good.open());
}



// A client that subscribed to nothing gets nothing; one that unsubscribed gets nothing more.
TEST(FoxgloveServerLimits, NothingGoesToAClientThatDidNotSubscribe) {
  FoxgloveServer s(anyPort());
  const uint32_t ch = s.addChannel(channel("/pose", false));
  s.start();
  RawClient c(s.port());
  ASSERT_TRUE(c.open());
  s.publish(ch, 1, Bytes{'{', '}'});
  EXPECT_TRUE(c.drain(300).empty());
  ASSERT_TRUE(c.sendText(subscribeAll(4, 1, ch).dump()));
  ASSERT_TRUE(eventually([&] { return s.subscribed(ch); }));
  s.publish(ch, 2, Bytes{'{', '}'});
  EXPECT_EQ(c.next().opcode, 2);
  ASSERT_TRUE(c.sendText(json{{"op", "unsubscribe"}, {"subscriptionIds", {4}}}.dump()));
  ASSERT_TRUE(eventually([&] { return !s.subscribed(ch); }));
  s.publish(ch, 3, Bytes{'{', '}'});
  EXPECT_TRUE(c.drain(300).empty());
  EXPECT_EQ(s.stats().messages_sent, 1u);
  EXPECT_EQ(s.stats().messages_dropped, 0u);
}


}  // namespace polyloc::t_live_server
