// One client of the control server: its non-blocking socket, the parser over what it sent and
// the queue of reply bytes it has not read yet, plus the clocks the server's timeouts use.
// The server (server.cpp) decides what to do; this only moves bytes.
#pragma once

#include "protocol/frame.hpp"
#include "protocol/parser.hpp"

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace polyloc::protocol {

enum class CloseReason { None, Peer, FrameErrors, FrameTimeout, Idle, Slow, IoError, Busy, Stopped };
const char* toString(CloseReason r);  // "peer", "frame_errors", ...

class Connection {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Io { Data, WouldBlock, Eof, Error };

  Connection(int fd, std::string peer, uint32_t max_frame_bytes, Clock::time_point now);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  int fd() const { return fd_; }
  const std::string& peer() const { return peer_; }

  // One read of up to kReadChunk bytes; with `parse` they go to the parser, else dropped (a
  // closing connection drains what the peer still sends, so close() does not reset the reply).
  Io readSome(bool parse, size_t& bytes);
  FrameParser& parser() { return parser_; }

  void queue(const Frame& f) { appendFrame(out_, f.command, f.data); }
  size_t queued() const { return out_.size() - out_pos_; }
  // Writes what the socket takes now. Error: the peer is gone.
  Io flush(size_t& bytes);
  void shutdownWrite();

  // Server state of this connection.
  Clock::time_point last_rx;        // last bytes received (idle timeout)
  Clock::time_point frame_started;  // first byte of the incomplete frame (frame timeout)
  Clock::time_point connected;      // first-frame timeout
  uint64_t frames = 0;              // whole frames received
  int frame_errors = 0;
  CloseReason closing = CloseReason::None;  // set: no more requests; flush, drain, close
  Clock::time_point close_by;               // closing: give up waiting for the peer then
  bool write_shut = false;
  bool peer_eof = false;

  static constexpr size_t kReadChunk = 64 * 1024;

 private:
  int fd_;
  std::string peer_;
  FrameParser parser_;
  std::vector<uint8_t> out_;
  size_t out_pos_ = 0;
  std::vector<uint8_t> in_;
};

}  // namespace polyloc::protocol
