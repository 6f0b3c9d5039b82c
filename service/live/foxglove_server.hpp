// A Foxglove WebSocket server (protocol foxglove.websocket.v1, docs/live.md): advertises
// channels, lets clients subscribe, and sends each published message to its subscribers. Plain
// HTTP GET / on the same port answers one page (the live top view).
//
// Built on websocketpp (as Foxglove's own C++ server) and standalone asio, on a thread of its
// own. The publishing side never waits for a client: publish() hands the message over and
// returns; a client whose send queue is over `max_queue_bytes` loses that message (counted), and
// one that stays over it for `stall_timeout_s` is disconnected (counted). What a client can make
// the server hold is bounded too: connections that have not finished their handshake
// (`max_pending`, each closed after `handshake_timeout_s`), subscriptions (`max_subscriptions`),
// messages per second (`max_client_rate`); a latched message goes once per client and channel,
// through the same queue limit as any other.
//
//   FoxgloveServer s(cfg);
//   uint32_t pose = s.addChannel({"/pose", "cdr", "geometry_msgs/msg/PoseWithCovarianceStamped", schema, "ros2msg"});
//   s.start();                                   // binds; throws std::runtime_error naming address:port
//   if (s.subscribed(pose)) s.publish(pose, stamp_ns, bytes);
//
// This header is C++17 (the server's own file is compiled as C++17: websocketpp 0.8 is not C++20).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace polyloc::live {

struct ServerConfig {
  std::string address = "127.0.0.1";  // loopback: the view is for the robot's own computer unless opened
  uint16_t port = 8765;               // 0: any free port (port() says which)
  int max_clients = 8;                // more are refused (HTTP 503)
  size_t max_queue_bytes = 8u << 20;  // per client: messages beyond it are dropped (an empty queue takes one of any size)
  double stall_timeout_s = 3.0;       // over the queue limit this long: disconnected
  size_t max_client_message = 64u << 10;  // bytes; a larger client message closes the client
  int max_bad_messages = 20;          // malformed client messages answered before the client is closed
  int max_pending = 16;               // connections before their handshake; more are closed at once
  double handshake_timeout_s = 3.0;   // a connection that has not finished its handshake by then is closed
  int max_subscriptions = 64;         // per client; more are refused (status error)
  double max_client_rate = 50;        // client messages per second (bursts of as many); more are refused
  std::string name = "polylocd";      // serverInfo.name
  std::string page;                   // the HTML answered on GET / (empty: 404)
};

struct ChannelSpec {
  std::string topic, encoding, schema_name, schema, schema_encoding;
  bool latched = false;  // the last message goes to every new subscriber (map, static transforms)
};

struct ServerStats {
  uint64_t clients = 0;             // connected now
  uint64_t connections = 0;         // accepted in all
  uint64_t refused = 0;             // refused: max_clients reached or no foxglove.websocket.v1
  uint64_t messages_sent = 0;       // message frames queued to clients
  uint64_t messages_dropped = 0;    // not sent: the client's queue was full
  uint64_t disconnected_slow = 0;   // clients closed for staying over the queue limit
  uint64_t bad_messages = 0;        // malformed or unsupported client messages
  uint64_t http_requests = 0;       // plain HTTP requests answered
  uint64_t refused_pending = 0;     // connections closed at once: max_pending handshakes in flight
  uint64_t rate_limited = 0;        // client messages refused: over max_client_rate
  uint64_t accept_errors = 0;       // failed accepts (e.g. no file descriptors left): retried after a pause
};

class FoxgloveServer {
 public:
  explicit FoxgloveServer(ServerConfig config);
  ~FoxgloveServer();  // stops
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  // Before start(); returns the channel id (1, 2, ...).
  uint32_t addChannel(const ChannelSpec& spec);
  void start();
  void stop();  // closes every client; idempotent
  uint16_t port() const;

  // Whether some client subscribed to the channel: publishers skip encoding otherwise. Lock-free.
  bool subscribed(uint32_t channel) const;
  // Thread-safe and never blocks on a client. A latched channel keeps the message for later
  // subscribers even when nobody is subscribed now.
  void publish(uint32_t channel, uint64_t stamp_ns, std::shared_ptr<const std::vector<uint8_t>> payload);
  void publish(uint32_t channel, uint64_t stamp_ns, std::vector<uint8_t> payload) {
    publish(channel, stamp_ns, std::make_shared<const std::vector<uint8_t>>(std::move(payload)));
  }
  ServerStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc::live
