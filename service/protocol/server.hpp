// The TCP control endpoint: one thread, poll() over non-blocking sockets, a parser and an
// output queue per client; requests go to the ControlHandler through dispatch(). Clients that
// send garbage, never finish a frame, or never read their replies get an error reply where one
// can still reach them and are closed; every case is counted and logged (rate-limited), and
// the other clients are served on. Rules in docs/protocol.md, "Connections".
#pragma once

#include "protocol/frame.hpp"
#include "protocol/handler.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace polyloc::protocol {

struct ServerConfig {
  std::string bind_address = "127.0.0.1";            // numeric IPv4/IPv6; loopback: this machine only
  uint16_t port = 0;                                 // 0: an ephemeral port, see Server::port()
  int max_clients = 16;                              // more: a Busy reply, then closed
  uint32_t max_frame_bytes = kDefaultMaxFrameBytes;  // larger requests: FrameTooLarge
  int frame_timeout_ms = 2000;                       // a started frame not complete after this: FrameTimeout, closed
  int first_frame_timeout_ms = 5000;                 // no whole frame this long after connecting: FrameTimeout, closed
  int idle_timeout_ms = 600000;                      // nothing received for this long: closed; 0: never
  size_t max_queued_bytes = 1 << 20;                 // replies a client has not read; over it: closed (slow)
  int max_frame_errors = 4;                          // frame errors on one connection before it is closed
  int close_linger_ms = 500;                         // a closing connection waits this long for its peer to read
};

// Totals since start(); a snapshot, safe to take from any thread.
struct ServerCounters {
  uint64_t accepted = 0, open = 0;
  uint64_t frames = 0, replies = 0, bytes_in = 0, bytes_out = 0;
  // Frame errors (FRAME_ERROR replies) by kind.
  uint64_t bad_magic = 0, bad_frame_size = 0, frame_too_large = 0, bad_crc = 0, frame_timeouts = 0;
  // Requests answered with an error status.
  uint64_t unknown_command = 0, bad_request = 0, not_available = 0, handler_failures = 0;
  // Connections closed, by reason.
  uint64_t closed_peer = 0, closed_frame_errors = 0, closed_frame_timeout = 0, closed_idle = 0, closed_slow = 0,
           closed_io_error = 0, closed_busy = 0, closed_stopped = 0;
};

class Server {
 public:
  Server(ServerConfig config, ControlHandler& handler);
  ~Server();  // stop()
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Binds, listens and starts the server thread. Throws std::invalid_argument naming a setting
  // that cannot work, std::runtime_error naming the address and the reason when the socket
  // cannot be bound, or std::logic_error when already running.
  void start();
  // Closes every connection and joins the thread; from any thread but the server's own (not
  // from a handler call); idempotent.
  void stop();
  bool running() const;
  uint16_t port() const;  // the bound port (the ephemeral one when config.port was 0)
  ServerCounters counters() const;
  const ServerConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc::protocol
