// A blocking client of the control protocol, for tests and for `polyloc ctl`: connect, send a
// request, wait for its reply with a timeout. Every failure throws std::runtime_error naming
// the server (host:port) and what went wrong; the reply's own status is the caller's to judge.
#pragma once

#include "protocol/frame.hpp"
#include "protocol/parser.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace polyloc::protocol {

struct ClientOptions {
  int timeout_ms = 2000;                 // connect, and each call's wait for its reply
  uint32_t max_frame_bytes = 16u << 20;  // replies can be large (scans)
};

class Client {
 public:
  Client(const std::string& host, uint16_t port, ClientOptions options = {});
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Sends the request and returns its reply: the frame with the request's id and bit 31 set,
  // or a FRAME_ERROR the server sent instead. Throws on timeout or a closed connection.
  Frame call(uint32_t command, std::span<const uint32_t> data = {});

  // Lower level, for tests: bytes as they are, and the next frame from the server (nullopt
  // after timeout_ms; throws when the server closed the connection or sent a broken frame).
  void sendBytes(std::span<const uint8_t> bytes);
  std::optional<Frame> receive(int timeout_ms);
  // True when the server closed the connection within timeout_ms (frames before it dropped).
  bool waitClosed(int timeout_ms);

  const std::string& server() const { return where_; }
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  std::string where_;
  ClientOptions opt_;
  FrameParser parser_;
};

}  // namespace polyloc::protocol
