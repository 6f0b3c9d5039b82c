#include "protocol/connection.hpp"

#include <cerrno>
#include <sys/socket.h>
#include <unistd.h>

namespace polyloc::protocol {

const char* toString(CloseReason r) {
  switch (r) {
    case CloseReason::None: return "none";
    case CloseReason::Peer: return "peer";
    case CloseReason::FrameErrors: return "frame_errors";
    case CloseReason::FrameTimeout: return "frame_timeout";
    case CloseReason::Idle: return "idle";
    case CloseReason::Slow: return "slow";
    case CloseReason::IoError: return "io_error";
    case CloseReason::Busy: return "busy";
    case CloseReason::Stopped: return "stopped";
  }
  return "unknown";
}

Connection::Connection(int fd, std::string peer, uint32_t max_frame_bytes, Clock::time_point now)
    : last_rx(now), frame_started(now), connected(now), fd_(fd), peer_(std::move(peer)), parser_(max_frame_bytes), in_(kReadChunk) {}

Connection::~Connection() {
  if (fd_ >= 0) ::close(fd_);
}

Connection::Io Connection::readSome(bool parse, size_t& bytes) {
  bytes = 0;
  for (;;) {
    const ssize_t n = ::recv(fd_, in_.data(), in_.size(), 0);
    if (n > 0) {
      bytes = static_cast<size_t>(n);
      if (parse) parser_.push({in_.data(), bytes});
      return Io::Data;
    }
    if (n == 0) return Io::Eof;
    if (errno == EINTR) continue;
    return errno == EAGAIN || errno == EWOULDBLOCK ? Io::WouldBlock : Io::Error;
  }
}

Connection::Io Connection::flush(size_t& bytes) {
  bytes = 0;
  while (queued() > 0) {
    const ssize_t n = ::send(fd_, out_.data() + out_pos_, queued(), MSG_NOSIGNAL);
    if (n > 0) {
      out_pos_ += static_cast<size_t>(n), bytes += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    return Io::Error;
  }
  // Keep the queue's memory bounded by what is unsent.
  if (out_pos_ == out_.size())
    out_.clear(), out_pos_ = 0;
  else if (out_pos_ > (1u << 16) && out_pos_ > out_.size() / 2)
    out_.erase(out_.begin(), out_.begin() + static_cast<std::ptrdiff_t>(out_pos_)), out_pos_ = 0;
  return queued() > 0 ? Io::WouldBlock : Io::Data;
}

void Connection::shutdownWrite() {
  if (!write_shut) ::shutdown(fd_, SHUT_WR);
  write_shut = true;
}

}  // namespace polyloc::protocol
